// The vtou row kernels (instance matching's inner loop): the depth test as a
// float window is the double formula exactly, and every SIMD version cuts a
// row into the same spans as a plain loop over the formula.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "map_scratch.h"
#include "mask_footprint.h"
#include "mask_row_kernels.h"

namespace pndt::test
{
namespace
{
bool formula(float d, double z0, double tol) { return std::abs(double(d) - z0) <= tol; }
bool inWindow(float d, DepthWindow w) { return w.lo <= d && d <= w.hi; }

/// The loop footprintSpans ran before the kernels, on the formula itself.
std::vector<MaskSpan> reference(const int32_t* predicted, const float* depth, int c0, int c1, double z0, double tol,
                                uint32_t row, const int32_t* to_frame)
{
    std::vector<MaskSpan> out;
    int32_t run_p = kUnmappedPixel;
    int run_begin = 0;
    for (int c = c0; c <= c1 + 1; ++c)
    {
        const int32_t q = c > c1 || predicted[c] == kUnmappedPixel || !formula(depth[c], z0, tol) ? kUnmappedPixel
                                                                                                : predicted[c];
        if (q == run_p && c <= c1) continue;
        if (run_p != kUnmappedPixel)
            out.push_back({row + uint32_t(run_begin), row + uint32_t(c), run_p >= 0 ? to_frame[run_p] : run_p});
        run_p = q;
        run_begin = c;
    }
    return out;
}
/// got == want span by span (kernel v, case k in the messages).
void expectSameSpans(const std::vector<MaskSpan>& got, const std::vector<MaskSpan>& want, size_t v, int k)
{
    ASSERT_EQ(got.size(), want.size()) << "kernel " << v << " case " << k;
    for (size_t i = 0; i < want.size(); ++i)
    {
        ASSERT_EQ(got[i].begin, want[i].begin) << "kernel " << v << " case " << k << " span " << i;
        ASSERT_EQ(got[i].end, want[i].end) << "kernel " << v << " case " << k << " span " << i;
        ASSERT_EQ(got[i].predicted, want[i].predicted) << "kernel " << v << " case " << k << " span " << i;
    }
}
}  // namespace

TEST(MaskRowKernels, TheDepthWindowIsTheDoubleFormulaForEveryFloatNearItsEnds)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> z(0.05, 12.0), t(0.0, 0.3);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    size_t checked = 0;
    for (int k = 0; k < 2000; ++k)
    {
        // Random depths and tolerances, and ones on float values (the ends exact).
        double z0 = z(rng), tol = t(rng);
        if (k % 4 == 1) z0 = double(float(z0));
        if (k % 4 == 2) tol = 0.0;
        if (k % 4 == 3) tol = double(float(tol));
        const DepthWindow w = depthWindow(z0, tol);
        ASSERT_TRUE(formula(w.lo, z0, tol) || w.lo > w.hi) << z0 << " " << tol;
        for (float end : {float(z0 - tol), float(z0 + tol), w.lo, w.hi})
        {
            float d = end;
            for (int s = 0; s < 4; ++s) d = std::nextafter(d, -kInf);
            for (int s = 0; s < 9; ++s, d = std::nextafter(d, kInf), ++checked)
                ASSERT_EQ(inWindow(d, w), formula(d, z0, tol)) << "z0 " << z0 << " tol " << tol << " d " << d;
        }
        for (float d : {0.f, -0.f, kInf, -kInf, std::numeric_limits<float>::quiet_NaN(), float(z0)})
            ASSERT_EQ(inWindow(d, w), formula(d, z0, tol)) << d;
    }
    EXPECT_GT(checked, 70000u);
    // Hand-checked: 2 m with a 5 cm tolerance. 1.95f = 1.95000005 and 2.05f = 2.04999995
    // both pass; the floats beyond them (1.94999993, 2.05000019) do not: the window is
    // exactly [1.95f, 2.05f].
    const DepthWindow w = depthWindow(2.0, 0.05);
    EXPECT_EQ(w.lo, 1.95f);
    EXPECT_EQ(w.hi, 2.05f);
    // A negative tolerance passes nothing.
    const DepthWindow none = depthWindow(2.0, -1.0);
    EXPECT_FALSE(inWindow(2.f, none));
}

// Windows whose ends lie at or across zero, among denormals, or at the floats'
// ends: where stepping a float by its bits must turn at the sign.
TEST(MaskRowKernels, TheDepthWindowAcrossZeroDenormalsAndTheFloatsEnds)
{
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const double tiny = double(std::numeric_limits<float>::denorm_min());
    const double big = double(std::numeric_limits<float>::max());
    size_t checked = 0;
    for (const double z0 : {0.0, tiny, -tiny, 3 * tiny, 1e-40, -1e-40, 1e-4, -0.5, big, -big})
        for (const double tol : {0.0, tiny, 2.5 * tiny, 1e-39, 1e-3, 0.7})
        {
            const DepthWindow w = depthWindow(z0, tol);
            for (float end : {float(z0 - tol), float(z0 + tol), w.lo, w.hi, 0.f, -0.f})
            {
                float d = end;
                for (int s = 0; s < 4; ++s) d = std::nextafter(d, -kInf);
                for (int s = 0; s < 9; ++s, d = std::nextafter(d, kInf), ++checked)
                    ASSERT_EQ(inWindow(d, w), formula(d, z0, tol)) << "z0 " << z0 << " tol " << tol << " d " << d;
            }
        }
    EXPECT_GT(checked, 3000u);
    // By hand: at 0 with a tolerance of 2.5 denormals, the floats -2, ..., 2 denormals pass.
    const DepthWindow w = depthWindow(0.0, 2.5 * tiny);
    EXPECT_EQ(w.lo, float(-2 * tiny));
    EXPECT_EQ(w.hi, float(2 * tiny));
}

TEST(MaskRowKernels, EveryVersionCutsARowIntoTheSameSpans)
{
    std::vector<MaskRowFn> kernels{&maskRowScalar};
    if (MaskRowFn k = maskRowAvx2()) kernels.push_back(k);
    if (MaskRowFn k = maskRowAvx512()) kernels.push_back(k);
    std::printf("[measured] row kernels on this CPU: %zu (scalar%s%s)\n", kernels.size(),
                maskRowAvx2() ? ", AVX2" : "", maskRowAvx512() ? ", AVX-512" : "");
    std::mt19937 rng(11);
    const int W = 100;
    std::vector<int32_t> predicted(W);
    std::vector<float> depth(W);
    const std::vector<int32_t> to_frame{5, 3, 9, 0, 7};
    size_t spans = 0;
    for (int k = 0; k < 4000; ++k)
    {
        // Runs of one predicted index (band-local 0..4, -1 none, unmapped), depths
        // around z0 with NaN, zero and infinite pixels, the tolerance's ends exactly.
        const double z0 = 1.0 + 0.01 * (k % 300), tol = 0.05 * (1 + k % 3);
        int32_t p = 0;
        for (int c = 0; c < W; ++c)
        {
            if (rng() % 6 == 0) p = int32_t(rng() % 7) - 2;
            predicted[size_t(c)] = p;
            switch (rng() % 10)
            {
                case 0: depth[size_t(c)] = std::numeric_limits<float>::quiet_NaN(); break;
                case 1: depth[size_t(c)] = 0.f; break;
                case 2: depth[size_t(c)] = std::numeric_limits<float>::infinity(); break;
                case 3: depth[size_t(c)] = float(z0 + (rng() % 2 ? tol : -tol)); break;
                default: depth[size_t(c)] = float(z0 + (double(rng() % 1000) / 1000.0 - 0.5) * 4 * tol);
            }
        }
        const int c0 = int(rng() % W), c1 = c0 + int(rng() % (W - c0));
        const uint32_t row = 640u * uint32_t(k % 480);
        const auto want = reference(predicted.data(), depth.data(), c0, c1, z0, tol, row, to_frame.data());
        spans += want.size();
        for (size_t v = 0; v < kernels.size(); ++v)
        {
            std::vector<MaskSpan> got(size_t(c1 - c0 + 2));
            got.resize(kernels[v](predicted.data(), depth.data(), c0, c1, depthWindow(z0, tol), row, to_frame.data(),
                                  got.data()));
            ASSERT_NO_FATAL_FAILURE(expectSameSpans(got, want, v, k));
        }
    }
    EXPECT_GT(spans, 20000u);  // the cases do cut rows into many runs
}

TEST(MaskRowKernels, EveryFootprintVersionGivesTheRowByRowSpans)
{
    std::vector<MaskFootprintFn> kernels{&maskFootprintScalar};
    if (MaskFootprintFn k = maskFootprintAvx2()) kernels.push_back(k);
    if (MaskFootprintFn k = maskFootprintAvx512()) kernels.push_back(k);
    std::mt19937 rng(13);
    const int W = 64, H = 48;
    std::vector<int32_t> predicted(size_t(W * H));
    std::vector<float> depth(size_t(W * H));
    // Two row bands with their own translations of the predicted indices.
    const std::vector<int32_t> top{5, 3, 9, 0, 7}, bottom{2, 8, 1, 6, 4};
    std::vector<const int32_t*> row_remap(static_cast<size_t>(H));
    for (int r = 0; r < H; ++r) row_remap[size_t(r)] = r < H / 2 ? top.data() : bottom.data();
    const double k2 = 3.0;
    size_t spans = 0, rows_used = 0;
    for (int k = 0; k < 600; ++k)
    {
        const double z0 = 2.0, tol = 0.1;
        int32_t p = 0;
        for (size_t i = 0; i < predicted.size(); ++i)
        {
            if (rng() % 5 == 0) p = int32_t(rng() % 7) - 2;
            predicted[i] = p;
            depth[i] = rng() % 8 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                      : float(z0 + (double(rng() % 1000) / 1000.0 - 0.5) * 3 * tol);
        }
        // An ellipse (or, every fourth case, a box) partly outside the image.
        MaskFootprint fp;
        fp.ellipse = k % 4 != 0;
        fp.u0 = double(rng() % 80) - 8.0 + 0.37;
        fp.v0 = double(rng() % 60) - 6.0 + 0.61;
        const double sx = 1.0 + double(rng() % 200) / 10.0, sy = 1.0 + double(rng() % 200) / 10.0;
        const double rho = (double(rng() % 180) - 90.0) / 100.0;
        const double det = sx * sx * sy * sy * (1 - rho * rho);
        fp.s00 = sy * sy / det;
        fp.s01 = -rho * sx * sy / det;
        fp.s11 = sx * sx / det;
        fp.c0 = std::max(0, int(std::ceil(fp.u0 - std::sqrt(k2) * sx)));
        fp.c1 = std::min(W - 1, int(std::floor(fp.u0 + std::sqrt(k2) * sx)));
        fp.r0 = std::max(0, int(std::ceil(fp.v0 - std::sqrt(k2) * sy)));
        fp.r1 = std::min(H - 1, int(std::floor(fp.v0 + std::sqrt(k2) * sy)));
        fp.z0 = z0;
        // What footprintSpans did before the footprint kernels: row by row.
        std::vector<MaskSpan> want;
        for (int r = fp.r0; r <= fp.r1; ++r)
        {
            int a, b;
            if (!footprintRow(fp, r, k2, a, b)) continue;
            ++rows_used;
            const uint32_t row = uint32_t(r * W);
            const auto part =
                reference(&predicted[row], &depth[row], a, b, z0, tol, row, row_remap[size_t(r)]);
            want.insert(want.end(), part.begin(), part.end());
        }
        spans += want.size();
        for (size_t v = 0; v < kernels.size(); ++v)
        {
            std::vector<MaskSpan> got(size_t(W * H));
            got.resize(kernels[v](fp, k2, predicted.data(), depth.data(), W, depthWindow(z0, tol), row_remap.data(),
                                  got.data()));
            ASSERT_NO_FATAL_FAILURE(expectSameSpans(got, want, v, k));
        }
    }
    EXPECT_GT(rows_used, 5000u);  // footprints of many rows, in both bands
    EXPECT_GT(spans, 20000u);
}

namespace
{
/// Every footprint version's spans on an image where every pixel passes (one
/// predicted instance, depth z0): one span per row with a chord, [c0, c1 + 1).
std::vector<std::vector<MaskSpan>> footprintSpansOfEveryVersion(const MaskFootprint& fp, double k2, int W, int H)
{
    std::vector<MaskFootprintFn> kernels{&maskFootprintScalar};
    if (MaskFootprintFn k = maskFootprintAvx2()) kernels.push_back(k);
    if (MaskFootprintFn k = maskFootprintAvx512()) kernels.push_back(k);
    const std::vector<int32_t> predicted(size_t(W * H), 0), to_frame{7};
    const std::vector<float> depth(size_t(W * H), 2.f);
    const std::vector<const int32_t*> row_remap(size_t(H), to_frame.data());
    std::vector<std::vector<MaskSpan>> out;
    for (MaskFootprintFn k : kernels)
    {
        std::vector<MaskSpan> got(size_t(W * H));
        got.resize(k(fp, k2, predicted.data(), depth.data(), W, depthWindow(2.0, 0.1), row_remap.data(), got.data()));
        out.push_back(got);
    }
    return out;
}
}  // namespace

// The SIMD versions compute the rows' chords four at a time: the chord ends
// must land on the same pixels as footprintRow's, also where they fall exactly
// on a pixel centre, beyond the image, or nowhere.
TEST(MaskRowKernels, EveryFootprintVersionEndsChordsOnTheSamePixels)
{
    const int W = 64, H = 48;
    MaskFootprint circle;  // radius 4 (k2 = 16, unit covariance) about pixel (20, 20)
    circle.ellipse = true;
    circle.u0 = 20;
    circle.v0 = 20;
    circle.s00 = circle.s11 = 1;
    circle.c0 = 0;
    circle.c1 = W - 1;
    circle.r0 = 0;  // rows 0-47: three batches of rows and a part
    circle.r1 = H - 1;
    // Half chords sqrt(16 - dv^2), by hand: dv 0 -> 4, 1 -> 3.87, 2 -> 3.46,
    // 3 -> 2.65, 4 -> 0 (one pixel, an end exactly on a centre).
    const int half[5] = {4, 3, 3, 2, 0};
    for (const std::vector<MaskSpan>& spans : footprintSpansOfEveryVersion(circle, 16.0, W, H))
    {
        ASSERT_EQ(spans.size(), 9u);
        for (int dv = -4; dv <= 4; ++dv)
        {
            const MaskSpan& s = spans[size_t(dv + 4)];
            const uint32_t row = uint32_t((20 + dv) * W);
            EXPECT_EQ(s.begin, row + uint32_t(20 - half[std::abs(dv)])) << dv;
            EXPECT_EQ(s.end, row + uint32_t(20 + half[std::abs(dv)] + 1)) << dv;
            EXPECT_EQ(s.predicted, 7);
        }
    }

    // A vast, tilted ellipse: every chord reaches past the image (its ends
    // clamped to +-1e9 before the box), rows 3-40 (38: batches of 16, 16, 6).
    MaskFootprint vast = circle;
    vast.s00 = vast.s11 = 1e-20;
    vast.s01 = 3e-21;
    vast.c0 = 5;
    vast.c1 = 50;
    vast.r0 = 3;
    vast.r1 = 40;
    for (const std::vector<MaskSpan>& spans : footprintSpansOfEveryVersion(vast, 16.0, W, H))
    {
        ASSERT_EQ(spans.size(), 38u);
        for (size_t j = 0; j < spans.size(); ++j)
        {
            EXPECT_EQ(spans[j].begin, uint32_t((3 + int(j)) * W + 5));
            EXPECT_EQ(spans[j].end, uint32_t((3 + int(j)) * W + 51));
        }
    }

    // No chord anywhere: a degenerate inverse covariance (qa <= 0), a NaN centre.
    for (const double qa : {0.0, -1.0})
    {
        MaskFootprint flat = circle;
        flat.s00 = qa;
        for (const std::vector<MaskSpan>& spans : footprintSpansOfEveryVersion(flat, 16.0, W, H))
            EXPECT_TRUE(spans.empty()) << qa;
    }
    MaskFootprint lost = circle;
    lost.v0 = std::numeric_limits<double>::quiet_NaN();
    for (const std::vector<MaskSpan>& spans : footprintSpansOfEveryVersion(lost, 16.0, W, H))
        EXPECT_TRUE(spans.empty());
}

}  // namespace pndt::test
