// Paper steps 1-2: forward mapping of pixels to voxels, NDT shape and hit
// update, and NDT-aware free space along the rays.
//
// Parallel and deterministic: the image is cut into row bands (four per
// thread), each with its own voxel table; the tables are merged in band order,
// which gives the frame's voxels in order of their first pixel whatever the
// number of bands, and the sample sums are integers, so their order does not
// matter. Rays are cast in small chunks, each thread first from its own share
// of them; each thread records the strongest miss per voxel in its own brick
// blocks (or, MissAccumulation::PerRay, the integer sum of every ray's miss);
// the minimum (sum) over the threads is again order-free, and new voxels are
// created in brick order.
#include <pndt/free_space.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <type_traits>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "frame_pixels.h"
#include "map_scratch.h"

namespace pndt
{
namespace
{
inline uint64_t packKey(int32_t x, int32_t y, int32_t z)
{
    return VoxelKey{x, y, z}.packed();
}

/// One axis of a ray as its walk takes it: how the voxel's slot moves (within
/// the brick, or wrapping into the next brick), the axis's byte of the brick
/// counters, and the side of the brick the step leaves through.
struct RayAxisStep
{
    int32_t slot_step, slot_wrap;
    uint32_t count, refill;
    int32_t side;
};

/// A ray being walked voxel by voxel (Amanatides & Woo): the parameters t at
/// which it crosses the next voxel boundary of each axis and their increments,
/// its voxel's slot within the current brick and that brick's block.
/// `counters`: per axis (a byte each), 0x80 + the steps it has left in the
/// brick; a step past the brick clears the byte's top bit (no borrow reaches
/// the next byte). `axis`: the steps by the axis taken, indexed z, x, y (as
/// stepRay finds it). `enter` >= 0: the ray just entered the brick on that
/// side of `blk` (-x,+x,-y,+y,-z,+z), whose block is not linked yet.
struct RayWalk
{
    double t[3], d[3];
    uint32_t slot, counters;
    RayAxisStep axis[3];
    RayBlock* blk;
    int enter = -1;

    /// Sets the axes, counters and slot of a ray from the voxel `k` (coordinates) with steps `step` (-1, 0, 1).
    template <int BB>
    void setAxes(const int32_t* k, const int* step)
    {
        constexpr int32_t BM = (1 << BB) - 1;
        counters = 0;
        for (int a = 0; a < 3; ++a)
        {
            const int32_t l = k[a] & BM, unit = int32_t(1) << (BB * a);
            const uint32_t left = uint32_t(step[a] > 0 ? BM - l : step[a] < 0 ? l : BM);
            counters |= (0x80u + left) << (8 * a);
            RayAxisStep& e = axis[(a + 1) % 3];  // stepRay's index: z 0, x 1, y 2
            e.slot_step = step[a] * unit;
            e.slot_wrap = -BM * step[a] * unit;
            e.count = 1u << (8 * a);
            e.refill = uint32_t(BM + 1) << (8 * a);
            e.side = 2 * a + (step[a] > 0);
        }
        slot = uint32_t((k[0] & BM) | ((k[1] & BM) << BB) | ((k[2] & BM) << (2 * BB)));
    }
};

/// What stepRay notes of a piece of a ray: each voxel's block and slot, and
/// which voxels the task had not met yet (a ray meets a voxel once, so these
/// are distinct).
template <int N>
struct RayPiece
{
    RayBlock* block[N];
    uint32_t slot[N];
    uint32_t unseen[N];
    uint32_t gaussian[N];  ///< voxels classified as Gaussians before the piece (more join after)
    int unseen_count = 0;
    int gaussian_count = 0;
};

/// Notes voxels i..n-1 of a piece of the ray (`last`: the ray ends with the
/// piece) and moves the ray on. Returns n, or earlier the index after a voxel
/// whose step entered a brick not linked to the current block yet (`enter`
/// set: the caller links it and calls again). The axis of the smallest t is
/// taken, ties broken as walkSegment does (x before z, y before z, y before
/// x), by compare masks without a branch. Called out of line (the wrappers
/// below) and without calls, so that the ray stays in registers: inlined in the
/// walk, whose rare paths call out, the compiler kept the ray in memory and
/// turned its selects into jumps that mispredict. Leaving a brick is a branch
/// (about one step in eight): masks there measured slower, as the next voxel's
/// state load then waits on the brick counters.
template <int BB, int N>
[[gnu::always_inline]] inline int stepRayImpl(RayWalk& r, RayPiece<N>& p, int i, int n, bool last)
{
    static_assert(BB >= 1 && BB <= 6, "a brick counter is a byte: 0x80 + up to 0x7f steps");
    constexpr uint32_t kInBrick = 0x808080;  // every counter's top bit
    uint32_t slot = r.slot, counters = r.counters;
    const RayAxisStep* const axes = r.axis;
    RayBlock* blk = r.blk;
    int unseen = p.unseen_count, gaussians = p.gaussian_count;
#ifdef __SSE2__
    __m128d t0 = _mm_set_sd(r.t[0]), t1 = _mm_set_sd(r.t[1]), t2 = _mm_set_sd(r.t[2]);
    const __m128d d0 = _mm_set_sd(r.d[0]), d1 = _mm_set_sd(r.d[1]), d2 = _mm_set_sd(r.d[2]);
    const __m128d ones = _mm_castsi128_pd(_mm_set1_epi64x(-1));
#else
    double t0 = r.t[0], t1 = r.t[1], t2 = r.t[2];
    const double d0 = r.d[0], d1 = r.d[1], d2 = r.d[2];
#endif
    while (i < n)
    {
        p.block[i] = blk;
        p.slot[i] = slot;
        p.unseen[unseen] = uint32_t(i);
        p.gaussian[gaussians] = uint32_t(i);
        const int32_t state = blk->state[slot];
        unseen += state == RayBlock::kUnseen;
        gaussians += state > 0;
        ++i;
        if (last && i == n) break;  // no step past the ray's last voxel
#ifdef __SSE2__
        const __m128d c01 = _mm_cmplt_sd(t0, t1), c02 = _mm_cmplt_sd(t0, t2), c12 = _mm_cmplt_sd(t1, t2);
        const __m128d mx = _mm_and_pd(c01, c02), my = _mm_andnot_pd(c01, c12);
        const __m128d mz = _mm_xor_pd(_mm_or_pd(mx, my), ones);
        t0 = _mm_add_sd(t0, _mm_and_pd(mx, d0));  // + 0 where the axis is not taken, as walkSegment
        t1 = _mm_add_sd(t1, _mm_and_pd(my, d1));
        t2 = _mm_add_sd(t2, _mm_and_pd(mz, d2));
        const RayAxisStep& e = axes[_mm_movemask_pd(_mm_unpacklo_pd(mx, my))];  // x 1, y 2, z 0
#else
        const bool c01 = t0 < t1, c02 = t0 < t2, c12 = t1 < t2;
        const bool tx = c01 & c02, ty = !c01 & c12, tz = !(tx | ty);
        t0 += tx ? d0 : 0.0;
        t1 += ty ? d1 : 0.0;
        t2 += tz ? d2 : 0.0;
        const RayAxisStep& e = axes[int(tx) | (int(ty) << 1)];
#endif
        counters -= e.count;
        const bool out = (counters & kInBrick) != kInBrick;  // left the brick
        slot += uint32_t(out ? e.slot_wrap : e.slot_step);
        counters += e.refill & (0u - uint32_t(out));
        RayBlock* nb = blk->neighbour[e.side];
        if (out & (nb == nullptr))
        {
            r.enter = e.side;
            break;
        }
        blk = out ? nb : blk;
    }
#ifdef __SSE2__
    r.t[0] = _mm_cvtsd_f64(t0);
    r.t[1] = _mm_cvtsd_f64(t1);
    r.t[2] = _mm_cvtsd_f64(t2);
#else
    r.t[0] = t0;
    r.t[1] = t1;
    r.t[2] = t2;
#endif
    r.slot = slot;
    r.counters = counters;
    r.blk = blk;
    p.unseen_count = unseen;
    p.gaussian_count = gaussians;
    return i;
}

constexpr int kRayPiece = 128;  ///< voxels of a ray stepped before they get their misses
using RayPieceOf = RayPiece<kRayPiece>;
using StepRayFn = int (*)(RayWalk&, RayPieceOf&, int, int, bool);
[[gnu::noinline]] int stepRayPortable(RayWalk& r, RayPieceOf& p, int i, int n, bool last)
{
    return stepRayImpl<VoxelStore::kBrickBits>(r, p, i, n, last);
}
#if defined(__x86_64__) && defined(__GNUC__)
// Three-operand (VEX) forms: the SSE2 build copies registers before each compare.
[[gnu::target("avx2"), gnu::noinline]] int stepRayAvx2(RayWalk& r, RayPieceOf& p, int i, int n, bool last)
{
    return stepRayImpl<VoxelStore::kBrickBits>(r, p, i, n, last);
}
StepRayFn bestStepRay() { return simdCap() >= SimdCap::Avx2 ? stepRayAvx2 : stepRayPortable; }
#else
StepRayFn bestStepRay() { return stepRayPortable; }
#endif

/// Per-frame constants of the projection (see ProjectionSetup).
void setupProjection(const CameraIntrinsics& K, const Pose& T, double voxel_size, double max_range,
                     ProjectionSetup& P)
{
    const double scale = kSampleScale / voxel_size;
    const Eigen::Matrix3d R = T.linear() * scale;
    const Eigen::Vector3d t = (T.translation() / voxel_size + Eigen::Vector3d::Constant(VoxelKey::kLimit)) * kSampleScale;
    for (int i = 0; i < 3; ++i)
    {
        P.t[i] = t[i];
        P.col[i].resize(size_t(K.width));
    }
    for (int c = 0; c < K.width; ++c)
    {
        const double x = (c - K.cx) / K.fx;
        for (int i = 0; i < 3; ++i) P.col[i][size_t(c)] = R(i, 0) * x;
    }
    P.row.resize(3 * size_t(K.height));
    for (int r = 0; r < K.height; ++r)
    {
        const double y = (r - K.cy) / K.fy;
        for (int i = 0; i < 3; ++i) P.row[3 * size_t(r) + i] = R(i, 1) * y + R(i, 2);
    }
    P.max_range = max_range;
}

/// Start of a task's share of n items.
inline size_t share(size_t n, int task, int tasks) { return n * size_t(task) / size_t(tasks); }
}  // namespace

void PanopticMap::projectPixels(const FramePixels& f, const Pose& T, FrameStats& st)
{
    Scratch& s = scratch();
    const int W = f.depth.width, H = f.depth.height;
    // More bands than threads, so that a thread held up elsewhere (a shared
    // machine) does not hold up the frame: idle threads take the next band.
    const int B = std::max(1, std::min(s.threads > 1 ? 4 * s.threads : 1, H));
    s.pixel_slot.resize(size_t(W) * H);
    setupProjection(f.K, T, grid_.voxelSize(), options_.max_range, s.projection);
    {
        // Whole frustum (to max_range) inside the grid: no per-pixel range test.
        const double cx = std::max(std::abs(f.K.cx), std::abs(W - 1 - f.K.cx)) / f.K.fx;
        const double cy = std::max(std::abs(f.K.cy), std::abs(H - 1 - f.K.cy)) / f.K.fy;
        const double reach = options_.max_range * std::sqrt(cx * cx + cy * cy + 1.0) / grid_.voxelSize() + 2.0;
        const Eigen::Vector3d c = T.translation() / grid_.voxelSize();
        s.projection.inside = c.cwiseAbs().maxCoeff() + reach < double(VoxelKey::kLimit) - 2.0;
    }
    if (s.bands.size() < size_t(B)) s.bands.resize(size_t(B));
    s.band_count = B;

    // The bands are merged into band 0 in band order: frame slots stay in order
    // of their first pixel, as with a single band. Pixels keep their band's
    // local slot and readers translate with the band's remap (identity for
    // band 0): that saves a pass over the image. Each band is also the home of
    // the voxels it saw first (a contiguous range of slots).
    ProjectionBand& g = s.bands[0];
    const auto mergeBand = [&](int b) {
        ProjectionBand& band = s.bands[size_t(b)];
        band.remap.resize(band.count);
        if (b == 0)
        {
            g.home_begin = 0;
            g.home_end = g.count;
            for (uint32_t j = 0; j < g.count; ++j) g.remap[j] = j;
            return;
        }
        band.home_begin = g.count;
        for (uint32_t j = 0; j < band.count; ++j)
        {
            const HitSlot& h = band.hits[j];
            const auto [it, inserted] = g.index.try_emplace(h.key, g.count);
            if (inserted)
            {
                g.newHit() = h;
                g.last_row.push_back(band.last_row[j]);
            }
            else
            {
                g.hits[it->second].add(h);
                g.last_row[it->second] = std::max(g.last_row[it->second], band.last_row[j]);
            }
            band.remap[j] = it->second;
        }
        band.home_end = g.count;
        g.points.insert(g.points.end(), band.points.begin(), band.points.end());
    };
    if (s.pool)
    {
        // A thread that finishes a band merges every band that is ready in
        // order, while the others still project: the merge is off the
        // critical path but for the last band. One merger at a time; a thread
        // that finds the merge taken leaves its band to the merger, who looks
        // again after letting go.
        s.merged_bands = 0;
        s.band_done.reset(B);
        const auto mergeReady = [&] {
            for (;;)
            {
                std::unique_lock<std::mutex> lock(s.band_merge, std::try_to_lock);
                if (!lock.owns_lock()) return;
                while (s.merged_bands < B && s.band_done.isSet(s.merged_bands)) mergeBand(s.merged_bands++);
                const int next = s.merged_bands;
                lock.unlock();
                // Pairs with the fence after set(): either this sees the band
                // that thread finished, or that thread sees the lock free.
                std::atomic_thread_fence(std::memory_order_seq_cst);
                if (next >= B || !s.band_done.isSet(next)) return;
            }
        };
        s.pool->run(B, [&](int b) {
            projectBand(f, T, b, B);
            s.band_done.set(b);
            std::atomic_thread_fence(std::memory_order_seq_cst);
            mergeReady();
        });
        while (s.merged_bands < B) mergeBand(s.merged_bands++);  // none left: the last finisher merged them
    }
    else
    {
        projectBand(f, T, 0, 1);
        mergeBand(0);
    }

    // How far down the image each band's voxels reach (once all are merged).
    for (int b = 0; b < B; ++b)
    {
        ProjectionBand& band = s.bands[size_t(b)];
        band.home_last_row = H * b / B;
        for (uint32_t h = band.home_begin; h < band.home_end; ++h)
            band.home_last_row = std::max(band.home_last_row, g.last_row[h]);
    }

    st.pixels = uint64_t(W) * H;
    for (int b = 0; b < B; ++b)
    {
        const ProjectionBand& band = s.bands[size_t(b)];
        st.valid_pixels += band.valid;
        st.skipped_invalid_depth += band.invalid;
        st.skipped_over_range += band.over_range;
        st.skipped_outside_grid += band.outside;
    }
    st.hit_voxels = g.count;

    // The frame's voxels: existing ones looked up in parallel, new ones created
    // in slot order. Consecutive slots mostly share a brick.
    const auto lookup = [&](int t, int tasks) {
        uint64_t last_brick_key = ~uint64_t(0);
        const uint32_t* slots = nullptr;
        for (size_t i = share(g.count, t, tasks), e = share(g.count, t + 1, tasks); i < e; ++i)
        {
            HitSlot& h = g.hits[i];
            const VoxelKey k = VoxelKey::unpack(h.key);
            const uint64_t bk = VoxelStore::brickKeyOf(k);
            if (bk != last_brick_key)
            {
                const uint32_t brick = store_.brickOf(bk);
                slots = brick == kNoRecord ? nullptr : store_.slotsOf(brick);
                last_brick_key = bk;
            }
            h.voxel = slots ? slots[VoxelStore::slotOf(k)] : kNoRecord;
        }
    };
    const int lookup_tasks = s.pool && g.count >= 1024 ? 4 * s.threads : 1;
    if (lookup_tasks > 1)
        s.pool->run(lookup_tasks, [&](int t) { lookup(t, lookup_tasks); });
    else
        lookup(0, 1);
    for (uint32_t i = 0; i < g.count; ++i)
    {
        HitSlot& h = g.hits[i];
        if (h.voxel != kNoRecord) continue;
        const VoxelKey k = VoxelKey::unpack(h.key);
        h.voxel = store_.findOrCreateInBrick(store_.brickFor(VoxelStore::brickKeyOf(k)), VoxelStore::slotOf(k));
    }
    // A bit per voxel, not a frame stamp: 0.125 instead of 4 bytes per voxel.
    const size_t words = (store_.size() + 63) / 64;
    if (s.hit_bits.size() < words) s.hit_bits.resize(words + words / 4, 0);
    if (s.hit_bits_set) std::fill(s.hit_bits.begin(), s.hit_bits.end(), 0);
    s.hit_bits_set = true;
    for (uint32_t i = 0; i < g.count; ++i) s.hit_bits[g.hits[i].voxel >> 6] |= uint64_t(1) << (g.hits[i].voxel & 63);
}

namespace
{
/// One row's phase 2 of projectBand: what it reads and where it writes.
struct RowRuns
{
    const uint64_t* keys;
    const double *qxs, *qys, *qzs;
    const uint64_t* above_keys;  ///< the row above's keys (in this band), or its slots' row
    const int32_t* above;        ///< the row above's slots, nullptr in the band's first row
    int32_t* srow;               ///< this row's slots (written)
    int W, r;
    uint32_t row_begin;
    ProjectionBand* band;
    PixelSpan* span_out;
    uint64_t invalid, over, outside;
};

/// Runs of pixels in one voxel, their samples summed in registers as doubles holding exact
/// integers (a run is one row at most: < 2^53). Every product and sum is exact, so a fused
/// multiply-add (kFma) gives the same bits with fewer operations.
template <bool kFma>
[[gnu::always_inline]] inline void rowRunsImpl(RowRuns& io)
{
    const auto madd = [](double a, double b, double acc) {
        if constexpr (kFma)
            return __builtin_fma(a, b, acc);
        else
            return acc + a * b;
    };
    ProjectionBand& band = *io.band;
    const uint64_t* const keys = io.keys;
    const double *const qxs = io.qxs, *const qys = io.qys, *const qzs = io.qzs;
    const uint64_t* const above_keys = io.above_keys;
    const int32_t* const above = io.above;
    int32_t* const srow = io.srow;
    const int W = io.W, r = io.r;
    const uint32_t row_begin = io.row_begin;
    PixelSpan* span_out = io.span_out;
    uint64_t invalid = 0, over = 0, outside = 0;
    uint64_t run_key = kNoKey;
    int32_t run_slot = -1;
    // The voxel before the current run's: a surface on a voxel face
    // alternates two voxels pixel by pixel. At 1024x768 @ 10 cm runs are
    // ~5 pixels; of the runs the pixel above does not resolve, 3 in 5
    // return to the voxel before: no table lookup for them.
    uint64_t prev_key = kNoKey;
    int32_t prev_slot = -1;
    uint32_t rn = 0;
    double r_s0 = 0, r_s1 = 0, r_s2 = 0, r_xx = 0, r_xy = 0, r_xz = 0, r_yy = 0, r_yz = 0, r_zz = 0;
    // A run's pixels are consecutive and mapped: [c_end - rn, c_end).
    const auto flush = [&](int c_end) {
        if (rn == 0) return;
        *span_out++ = {row_begin + uint32_t(c_end) - rn, row_begin + uint32_t(c_end), uint32_t(run_slot)};
        band.last_row[size_t(run_slot)] = r;
        HitSlot& h = band.hits[size_t(run_slot)];
        h.count += rn;
        h.s[0] += int64_t(r_s0);
        h.s[1] += int64_t(r_s1);
        h.s[2] += int64_t(r_s2);
        h.ss[0] += int64_t(r_xx);
        h.ss[1] += int64_t(r_xy);
        h.ss[2] += int64_t(r_xz);
        h.ss[3] += int64_t(r_yy);
        h.ss[4] += int64_t(r_yz);
        h.ss[5] += int64_t(r_zz);
        rn = 0;
        r_s0 = r_s1 = r_s2 = r_xx = r_xy = r_xz = r_yy = r_yz = r_zz = 0;
    };
    for (int c = 0; c < W; ++c)
    {
        const uint64_t pk = keys[c];
        if (__builtin_expect(pk != run_key, 0))  // neighbouring pixels mostly share a voxel
        {
            if (pk >= kFirstSpecialKey)
            {
                invalid += pk == kInvalidKey;
                over += pk == kOverRangeKey;
                outside += pk == kOutsideKey;
                srow[c] = -1;
                flush(c);  // spans hold mapped pixels only
                run_key = kNoKey;
                continue;
            }
            flush(c);
            const uint64_t last_key = run_key;
            const int32_t last_slot = run_slot;
            run_key = pk;
            if (above && above_keys[c] == pk)
                run_slot = above[c];
            else if (pk == prev_key)
                run_slot = prev_slot;
            else
            {
                const auto [it, inserted] = band.index.try_emplace(pk, band.count);
                if (inserted)
                {
                    band.newHit().reset(pk);
                    band.last_row.push_back(r);
                }
                run_slot = int32_t(it->second);
            }
            if (last_key != kNoKey)
            {
                prev_key = last_key;
                prev_slot = last_slot;
            }
        }
        const double qx = qxs[c], qy = qys[c], qz = qzs[c];
        ++rn;
        r_s0 += qx;
        r_s1 += qy;
        r_s2 += qz;
        r_xx = madd(qx, qx, r_xx);
        r_xy = madd(qx, qy, r_xy);
        r_xz = madd(qx, qz, r_xz);
        r_yy = madd(qy, qy, r_yy);
        r_yz = madd(qy, qz, r_yz);
        r_zz = madd(qz, qz, r_zz);
        srow[c] = run_slot;
    }
    flush(W);
    io.span_out = span_out;
    io.invalid = invalid;
    io.over = over;
    io.outside = outside;
}

using RowRunsFn = void (*)(RowRuns&);
void rowRunsPortable(RowRuns& io) { rowRunsImpl<false>(io); }
#if defined(__x86_64__) && defined(__GNUC__)
// The baseline x86-64 build has no FMA: nine multiply-adds per pixel as a multiply and an
// add each. Every CPU with AVX2 has FMA.
[[gnu::target("fma")]] void rowRunsFma(RowRuns& io) { rowRunsImpl<true>(io); }
RowRunsFn bestRowRuns()
{
    static const bool fma = __builtin_cpu_supports("fma");
    return fma && simdCap() >= SimdCap::Avx2 ? rowRunsFma : rowRunsPortable;
}
#else
RowRunsFn bestRowRuns() { return rowRunsPortable; }
#endif
}  // namespace

void PanopticMap::projectBand(const FramePixels& f, const Pose& T, int b, int B)
{
    Scratch& s = *scratch_;
    ProjectionBand& band = s.bands[size_t(b)];
    band.clear();  // here, in parallel: clearing a voxel table costs its whole capacity
    const int W = f.depth.width, H = f.depth.height;
    const int r0 = H * b / B, r1 = H * (b + 1) / B;
    const bool per_pixel = options_.ray_mode == RayMode::PerPixel;
    const double vs = grid_.voxelSize();
    const ProjectionSetup& P = s.projection;
    // Two row buffers: the row above's keys tell whether a pixel's voxel is the
    // one of the pixel above, without touching the voxel table.
    band.rows[0].resize(W);
    band.rows[1].resize(W);
    const ProjectRowFn projectRow = bestProjectRow();
    const RowRunsFn runsOfRow = bestRowRuns();
    // Spans for the histogram pass (a row's pixels in one voxel). At most one
    // per pixel: reserved once per image size, never grown.
    band.spans.reserve(size_t(r1 - r0) * W);
    PixelSpan* const spans = band.spans.data();
    PixelSpan* span_out = spans;

    uint64_t invalid = 0, over = 0, outside = 0;
    for (int r = r0; r < r1; ++r)
    {
        const float* drow = &f.depth.data[size_t(r) * W];
        RowBuffer& row = band.rows[r & 1];
        const uint64_t* above_keys = band.rows[(r & 1) ^ 1].key.data();
        projectRow(P, &P.row[3 * size_t(r)], drow, 0, W, row);

        // Phase 2: runs of pixels in one voxel, their samples summed (runsOfRow).
        int32_t* srow = &s.pixel_slot[size_t(r) * W];
        const int32_t* above = r > r0 ? srow - W : nullptr;
        const uint64_t* keys = row.key.data();
        const double *qxs = row.q[0].data(), *qys = row.q[1].data(), *qzs = row.q[2].data();
        RowRuns rr{keys, qxs, qys, qzs, above_keys, above, srow, W, r, uint32_t(size_t(r) * W),
                   &band, span_out, 0, 0, 0};
        runsOfRow(rr);
        span_out = rr.span_out;
        invalid += rr.invalid;
        over += rr.over;
        outside += rr.outside;
        if (per_pixel)
            for (int c = 0; c < W; ++c)
                if (srow[c] >= 0)
                {
                    const VoxelKey k = VoxelKey::unpack(keys[c]);
                    band.points.emplace_back(grid_.minCorner(k) +
                                             (Eigen::Vector3d(qxs[c], qys[c], qzs[c]) +
                                              Eigen::Vector3d::Constant(double(kSampleHalf) + 0.5)) *
                                                 (vs / kSampleScale));
                }
    }
    band.spans.setSize(size_t(span_out - spans));
    band.valid = uint64_t(r1 - r0) * uint64_t(W) - invalid - over - outside;
    band.invalid = invalid;
    band.over_range = over;
    band.outside = outside;
}

void PanopticMap::updateShapes(FrameStats& st)
{
    Scratch& s = *scratch_;
    const uint32_t n = s.hitCount();
    HitSlot* hits = s.hits();
    const int tasks = (s.pool && n >= 256) ? 4 * s.threads : 1;
    // Voxels hit for the first time get a surface record, numbered in slot
    // order as one loop would: counted per task, then each task numbers its own.
    s.new_surfaces.assign(size_t(tasks) + 1, 0);
    const auto count = [&](int t) {
        uint32_t k = 0;
        for (size_t i = share(n, t, tasks), e = share(n, t + 1, tasks); i < e; ++i)
            k += store_[hits[i].voxel].surface == kNoRecord;
        s.new_surfaces[size_t(t) + 1] = k;
    };
    if (tasks > 1)
        s.pool->run(tasks, count);
    else
        count(0);
    for (int t = 0; t < tasks; ++t) s.new_surfaces[size_t(t) + 1] += s.new_surfaces[size_t(t)];
    const uint32_t first_new = uint32_t(surfaces_.size());
    SurfaceRecord* fresh = surfaces_.appendUnwritten(s.new_surfaces[size_t(tasks)]);
    // One hit log-odds per voxel and frame; all of its samples into the shape.
    const double q = grid_.voxelSize() / kSampleScale;
    const auto task = [&](int t) {
        uint32_t next_new = s.new_surfaces[size_t(t)];
        for (size_t i = share(n, t, tasks), e = share(n, t + 1, tasks); i < e; ++i)
        {
            const HitSlot& h = hits[i];
            Voxel& v = store_[h.voxel];
            if (v.surface == kNoRecord)
            {
                new (fresh + next_new) SurfaceRecord();
                v.surface = first_new + next_new++;
            }
            const Eigen::Vector3d corner = grid_.minCorner(VoxelKey::unpack(h.key));
            const double c = h.count;
            // Truncation put each sample at the low edge of its bin: + 0.5.
            const Eigen::Vector3d mean =
                corner + q * (Eigen::Vector3d(double(h.s[0]), double(h.s[1]), double(h.s[2])) / c +
                              Eigen::Vector3d::Constant(double(kSampleHalf) + 0.5));
            // Scatter sum (x-m)(x-m)^T = (n*ss - s s^T) / n, exactly in integers.
            const auto sc = [&](int ij, int a, int b) {
                const __int128 num = __int128(h.count) * h.ss[ij] - __int128(h.s[a]) * h.s[b];
                return double(num) / c * (q * q);
            };
            Eigen::Matrix3d S;
            S(0, 0) = sc(0, 0, 0);
            S(0, 1) = S(1, 0) = sc(1, 0, 1);
            S(0, 2) = S(2, 0) = sc(2, 0, 2);
            S(1, 1) = sc(3, 1, 1);
            S(1, 2) = S(2, 1) = sc(4, 1, 2);
            S(2, 2) = sc(5, 2, 2);
            surfaces_[v.surface].shape.merge(h.count, mean, S, options_.ndt_sample_cap);
            v.occ = std::min(options_.log_odds_max, v.occ + options_.log_odds_hit);
        }
    };
    if (tasks > 1)
        s.pool->run(tasks, task);
    else
        task(0);
    (void)st;
}

namespace
{
/// Rays a thread takes at a time. A worker takes the tasks of the caller's
/// stages (matching, histograms) between chunks: at 5 cm a chunk is ~25 us.
constexpr size_t kRayChunk = 64;
}  // namespace

void PanopticMap::prepareRays(const Pose& T)
{
    Scratch& s = *scratch_;
    s.ray_origin = T.translation();
    s.ray_count = options_.ray_mode == RayMode::Merged ? s.hitCount() : s.bands[0].points.size();
    // Each thread collects its misses in its own blocks (the minimum over
    // threads does not depend on who cast which ray). Each thread walks a
    // contiguous share of the rays, in small chunks, and then takes the chunks
    // left in the others' shares: neighbouring rays cross the same bricks, so
    // a brick mostly lives in one thread's blocks, classified once and merged
    // from one block (interleaved chunks made every thread visit every brick).
    const int threads = s.pool ? s.threads : 1;
    if (s.ray_workers.size() < size_t(threads)) s.ray_workers.resize(size_t(threads));
    for (int t = 0; t < threads; ++t) s.ray_workers[size_t(t)].clear();
    s.rays_parallel = threads > 1 && s.ray_count > kRayChunk;
    // Without rays_parallel the caller's share holds every ray (the others none).
    const int sharing = s.rays_parallel ? threads : 1;
    s.ray_shares.reset(threads);  // the same count every frame: no reallocation
    for (int t = 0; t < threads; ++t)
        s.ray_shares.set(t, t < sharing ? share(s.ray_count, t, sharing) : s.ray_count,
                         t < sharing ? share(s.ray_count, t + 1, sharing) : s.ray_count);
}

bool PanopticMap::castRayPiece(int thread)
{
    Scratch& s = *scratch_;
    // Otherwise every ray in one call, by the caller: only its blocks are merged.
    if (!s.rays_parallel && thread != 0) return false;
    const size_t chunk = s.rays_parallel ? kRayChunk : std::max<size_t>(1, s.ray_count);
    return s.ray_shares.drainOne(thread, chunk, [&](size_t i0, size_t i1, int) {
        castRays(s.ray_origin, i0, i1, s.ray_workers[size_t(thread)]);
    });
}

void PanopticMap::finishOccupancy(FrameStats& st)
{
    Scratch& s = *scratch_;
    const int threads = s.pool ? s.threads : 1;
    const size_t rays = s.ray_count;
    const int used = s.rays_parallel ? threads : 1;
    const HitSlot* hits = s.hits();
    for (uint32_t i = 0, n = s.hitCount(); i < n; ++i) s.hit_bits[hits[i].voxel >> 6] = 0;  // whole words: all were 0 before
    s.hit_bits_set = false;
    st.rays = rays;
    for (int t = 0; t < used; ++t) st.ray_steps += s.ray_workers[size_t(t)].steps;

    // Every thread's bricks, grouped by brick in key order (the creation order of new voxels).
    s.block_refs.clear();
    for (int t = 0; t < used; ++t)
    {
        const RayWorker& w = s.ray_workers[size_t(t)];
        for (uint32_t b = 0; b < w.block_count; ++b) s.block_refs.push_back({w.blocks[b]->brick_key, uint32_t(t), b});
    }
    std::sort(s.block_refs.begin(), s.block_refs.end());
    applyMisses(st);

    // Which thread casts which rays changes from frame to frame: every thread
    // keeps room for one block per brick and one Gaussian per voxel of this
    // frame, so that frames like it do not allocate, whoever does the work.
    // The Gaussians in view creep up while surfaces fill in (170, 174, 175 on
    // the same frame repeated): room for a quarter more is kept, and when that
    // runs short it doubles, so a creep does not allocate again.
    if (used > 1)
    {
        const size_t bricks = s.frame_bricks, gaussians = s.frame_gaussians;
        for (int t = 0; t < used; ++t)
        {
            RayWorker& w = s.ray_workers[size_t(t)];
            while (w.blocks.size() < bricks) w.blocks.push_back(std::make_unique<RayBlock>());
            if (w.gaussians.size() < gaussians + gaussians / 4) w.gaussians.resize(2 * gaussians);
            if (w.block_of.bucket_count() < 2 * bricks) w.block_of.reserve(bricks);
        }
        if (s.block_refs.capacity() < size_t(used) * bricks) s.block_refs.reserve(size_t(used) * bricks);
    }
}

void PanopticMap::castRays(const Eigen::Vector3d& origin, size_t i0, size_t i1, RayWorker& w)
{
    Scratch& s = *scratch_;
    const bool merged = options_.ray_mode == RayMode::Merged;
    const bool per_ray = options_.miss_accumulation == MissAccumulation::PerRay;
    const HitSlot* hits = s.hits();
    const double vs = grid_.voxelSize();
    const double q = vs / kSampleScale;
    const bool ndt = options_.use_ndt;
    const FastMissRule rule(MissModel{options_.miss_min_likelihood, options_.miss_likelihood_scale});
    const uint64_t* hit_bits = s.hit_bits.data();
    const VoxelKey k0 = grid_.keyOf(origin);
    constexpr int BB = VoxelStore::kBrickBits;

    // The block of a brick for this task, set up on first use in this frame.
    const auto blockOf = [&](int32_t bx, int32_t by, int32_t bz) -> RayBlock* {
        const uint64_t bk = packKey(bx, by, bz);
        const auto [it, inserted] = w.block_of.try_emplace(bk, w.block_count);
        if (!inserted) return w.blocks[it->second].get();
        if (w.block_count == w.blocks.size()) w.blocks.push_back(std::make_unique<RayBlock>());
        RayBlock* blk = w.blocks[w.block_count++].get();
        // Forget the previous use: only its touched slots are dirty.
        for (int word = 0; word < 8; ++word)
            for (uint64_t m = blk->touched[word]; m; m &= m - 1)
            {
                const int slot = word * 64 + __builtin_ctzll(m);
                blk->state[slot] = RayBlock::kUnseen;
                if (per_ray) blk->crossings[slot] = 0;  // untouched (not even read) otherwise
            }
        std::memset(blk->touched, 0, sizeof(blk->touched));
        for (auto& nb : blk->neighbour) nb = nullptr;
        blk->brick_key = bk;
        const uint32_t sb = store_.brickOf(bk);
        blk->slots = sb == kNoRecord ? nullptr : store_.slotsOf(sb);
        return blk;
    };
    // First visit of a voxel by this task (its record, or kNoRecord): may it
    // get a miss, and by which rule.
    const auto classify = [&](uint32_t vi) -> int32_t {
        if (vi == kNoRecord) return RayBlock::kConstant;
        if (hit_bits[vi >> 6] >> (vi & 63) & 1) return RayBlock::kSkip;  // a hit this frame wins
        if (!ndt) return RayBlock::kConstant;
        const Voxel& v = store_[vi];
        if (!hasGaussian(v)) return RayBlock::kConstant;
        if (w.gaussian_count == w.gaussians.size()) w.gaussians.emplace_back();
        MissGaussian& mg = w.gaussians[w.gaussian_count++];
        const NdtGaussian g = gaussianOf(v);
        mg.mean = g.mean;
        mg.info = g.info;
        mg.delta = 0.f;
        mg.sum = 0;
        return int32_t(w.gaussian_count);
    };

    // One ray (Amanatides & Woo, as walkSegment: the voxels from the origin's
    // up to but excluding the endpoint's, one per unit of Manhattan distance):
    // its walk, and what its misses depend on.
    struct Lane
    {
        RayWalk walk;
        int remaining = 0;
        Eigen::Vector3d dir, end;
        double sigma_end;
    };
    size_t next = i0;
    uint64_t steps = 0;
    RayBlock* origin_block = nullptr;
    // Loads the next ray with at least one voxel to walk; false when none is left.
    const auto start = [&](Lane& L) -> bool {
        while (next < i1)
        {
            const size_t i = next++;
            Eigen::Vector3d end;
            if (merged)
            {
                const HitSlot& h = hits[i];
                end = grid_.minCorner(VoxelKey::unpack(h.key)) +
                      q * (Eigen::Vector3d(double(h.s[0]), double(h.s[1]), double(h.s[2])) / double(h.count) +
                           Eigen::Vector3d::Constant(double(kSampleHalf) + 0.5));
            }
            else
                end = s.bands[0].points[i];
            const VoxelKey ke = grid_.keyOf(end);
            const Eigen::Vector3d d = end - origin;
            const int32_t k[3] = {k0.x, k0.y, k0.z};
            const int32_t ek[3] = {ke.x, ke.y, ke.z};
            int step[3];
            double t_max[3], t_delta[3];
            int remaining = 0;
            for (int a = 0; a < 3; ++a)
            {
                remaining += std::abs(ek[a] - k[a]);
                if (d[a] > 0)
                {
                    step[a] = 1;
                    t_delta[a] = vs / d[a];
                    t_max[a] = ((k[a] + 1) * vs - origin[a]) / d[a];
                }
                else if (d[a] < 0)
                {
                    step[a] = -1;
                    t_delta[a] = -vs / d[a];
                    t_max[a] = (k[a] * vs - origin[a]) / d[a];
                }
                else
                {
                    step[a] = 0;
                    t_delta[a] = t_max[a] = std::numeric_limits<double>::infinity();
                }
            }
            if (remaining == 0) continue;
            steps += uint64_t(remaining);
            const double range = d.norm();
            L.sigma_end = options_.sensor_sigma_base + options_.sensor_sigma_quadratic * range * range;
            L.dir = d;
            L.end = end;
            RayWalk& r = L.walk;
            for (int a = 0; a < 3; ++a)
            {
                r.t[a] = t_max[a];
                r.d[a] = t_delta[a];
            }
            r.setAxes<BB>(k, step);
            L.remaining = remaining;
            if (!origin_block) origin_block = blockOf(k[0] >> BB, k[1] >> BB, k[2] >> BB);  // every ray's first
            r.blk = origin_block;
            r.enter = -1;
            return true;
        }
        return false;
    };
    // Walks every ray, a piece of up to kRayPiece voxels at a time: stepRay notes
    // the voxels' blocks and slots and which of them this task meets first;
    // their records are then looked up together (a record is a cache miss more
    // often than not: its load starts before the one before it is needed),
    // and last the Gaussians among the voxels get their misses (a constant
    // miss needs no work per ray but PerRay's count). (Two rays stepped in
    // turn measured slower: the stepping is bound by its instructions, not by
    // its chains.)
    const StepRayFn stepRay = bestStepRay();
    const auto walk = [&](auto per_ray_tag) {
        constexpr bool kPerRay = decltype(per_ray_tag)::value;  // no test per step for the mode
        RayPieceOf p;
        uint32_t record[kRayPiece];
        Lane L;
        while (start(L))
        {
            RayWalk& ray = L.walk;
            for (int left = L.remaining; left > 0;)
            {
                const int n = std::min(left, kRayPiece);
                left -= n;
                p.unseen_count = p.gaussian_count = 0;
                for (int i = 0; i < n;)
                {
                    i = stepRay(ray, p, i, n, left == 0);
                    if (ray.enter >= 0)  // into a brick this task has not linked from here
                    {
                        // (the brick's coordinates from the block's key: fewer values
                        // for stepRay to keep in registers)
                        const VoxelKey from = VoxelKey::unpack(ray.blk->brick_key);
                        int32_t bc[3] = {from.x, from.y, from.z};
                        bc[ray.enter >> 1] += (ray.enter & 1) ? 1 : -1;
                        RayBlock* nb = blockOf(bc[0], bc[1], bc[2]);
                        ray.blk->neighbour[ray.enter] = nb;
                        nb->neighbour[ray.enter ^ 1] = ray.blk;
                        ray.blk = nb;
                        ray.enter = -1;
                    }
                }
                for (int k = 0; k < p.unseen_count; ++k)
                {
                    const int i = int(p.unseen[k]);
                    const uint32_t* slots = p.block[i]->slots;
                    const uint32_t vi = slots ? slots[p.slot[i]] : kNoRecord;
                    record[k] = vi;
                    if (vi != kNoRecord) __builtin_prefetch(&store_[vi]);
                }
                for (int k = 0; k < p.unseen_count; ++k)
                {
                    const int i = int(p.unseen[k]);
                    RayBlock& b = *p.block[i];
                    const uint32_t slot = p.slot[i];
                    const int32_t state = classify(record[k]);
                    b.state[slot] = state;
                    b.touched[slot >> 6] |= uint64_t(1) << (slot & 63);
                    p.gaussian[p.gaussian_count] = uint32_t(i);
                    p.gaussian_count += state > 0;
                }
                // Only a Gaussian's miss depends on the ray (the strongest miss and
                // the integer sums do not depend on the order they are taken in).
                for (int k = 0; k < p.gaussian_count; ++k)
                {
                    const int i = int(p.gaussian[k]);
                    MissGaussian& g = w.gaussians[size_t(p.block[i]->state[p.slot[i]] - 1)];
                    const float delta = float(rule(g.mean, g.info, origin, L.dir, L.end, L.sigma_end));
                    if constexpr (kPerRay)
                        g.sum += std::llround(double(delta) / kMissQuantum);
                    else if (delta < g.delta)
                        g.delta = delta;
                }
                if constexpr (kPerRay)
                    for (int i = 0; i < n; ++i)
                        if (p.block[i]->state[p.slot[i]] == RayBlock::kConstant) ++p.block[i]->crossings[p.slot[i]];
            }
        }
    };
    if (per_ray)
        walk(std::true_type{});
    else
        walk(std::false_type{});
    w.steps += steps;
}

void PanopticMap::applyMisses(FrameStats& st)
{
    Scratch& s = *scratch_;
    const float constant_miss = options_.log_odds_miss;
    const float log_odds_min = options_.log_odds_min;
    const float occupied_threshold = options_.occupied_threshold;
    const bool reset_freed = options_.reset_freed_voxels;
    const bool per_ray = options_.miss_accumulation == MissAccumulation::PerRay;
    const auto& refs = s.block_refs;
    const int threads = s.pool ? s.threads : 1;
    s.miss_groups.clear();
    if (s.own_groups.size() < size_t(threads)) s.own_groups.resize(size_t(threads));
    for (int t = 0; t < threads; ++t) s.own_groups[size_t(t)].clear();
    for (size_t a = 0; a < refs.size();)
    {
        size_t b = a + 1;
        while (b < refs.size() && refs[b].brick_key == refs[a].brick_key) ++b;
        s.own_groups[refs[a].worker].push_back(uint32_t(s.miss_groups.size()));
        s.miss_groups.push_back({a, b});
        a = b;
    }
    const size_t G = s.miss_groups.size();
    if (s.miss_chunks.size() < size_t(threads)) s.miss_chunks.resize(size_t(threads));
    for (int t = 0; t < threads; ++t) s.miss_chunks[size_t(t)].clear();
    s.fresh_misses.resize(G);

    // 1. Per brick, in parallel, each thread first on the bricks it walked: the
    //    strongest miss of every voxel the rays met (over all threads' blocks),
    //    applied at once where the voxel exists (each voxel belongs to one
    //    brick, one task) and kept for later where it does not.
    const auto missesOfGroup = [&](size_t g, MissChunk& c, uint32_t chunk) {
        const auto [a, b] = s.miss_groups[g];
        uint64_t touched[8];
        std::memcpy(touched, s.ray_workers[refs[a].worker].blocks[refs[a].block]->touched, sizeof(touched));
        for (size_t j = a + 1; j < b; ++j)
        {
            const RayBlock& o = *s.ray_workers[refs[j].worker].blocks[refs[j].block];
            for (int word = 0; word < 8; ++word) touched[word] |= o.touched[word];
        }
        const uint32_t brick = store_.brickOf(refs[a].brick_key);
        const uint32_t* slots = brick == kNoRecord ? nullptr : store_.slotsOf(brick);
        Scratch::FreshMisses& fresh = s.fresh_misses[g];
        fresh.chunk = chunk;
        fresh.begin = fresh.end = uint32_t(c.slot.size());
        for (int word = 0; word < 8; ++word)
            for (uint64_t m = touched[word]; m; m &= m - 1)
            {
                const uint32_t slot = uint32_t(word * 64 + __builtin_ctzll(m));
                float delta = 0.f;
                bool gaussian = false;
                // PerRay: every crossing ray's miss, summed (the paper's NDT-OM update;
                // clamping the sum once equals clamping after each ray, all being <= 0).
                uint64_t crossings = 0;
                int64_t sum = 0;
                for (size_t j = a; j < b; ++j)
                {
                    const RayWorker& w = s.ray_workers[refs[j].worker];
                    const RayBlock& blk = *w.blocks[refs[j].block];
                    const int32_t state = blk.state[slot];
                    if (state == RayBlock::kConstant)
                    {
                        delta = std::min(delta, constant_miss);
                        crossings += blk.crossings[slot];
                    }
                    else if (state > 0)
                    {
                        const MissGaussian& mg = w.gaussians[size_t(state - 1)];
                        delta = std::min(delta, mg.delta);
                        sum += mg.sum;
                        gaussian = true;
                    }
                }
                if (per_ray) delta = float(double(crossings) * constant_miss + double(sum) * kMissQuantum);
                c.gaussians += gaussian;
                if (!(delta < 0.f)) continue;
                ++c.misses;
                const uint32_t vi = slots ? slots[slot] : kNoRecord;
                if (vi == kNoRecord)
                {
                    c.slot.push_back(uint16_t(slot));
                    c.delta.push_back(delta);
                    continue;
                }
                Voxel& v = store_[vi];
                v.occ = std::max(log_odds_min, v.occ + delta);
                // A voxel that turned free has lost what it held (a moved chair).
                if (reset_freed && v.occ < occupied_threshold) resetVoxelContents(v);
            }
        fresh.end = uint32_t(c.slot.size());
    };
    constexpr size_t kGroupChunk = 8;
    if (threads > 1 && G >= 4 * kGroupChunk)
    {
        s.group_shares.reset(threads);
        for (int t = 0; t < threads; ++t) s.group_shares.set(t, 0, s.own_groups[size_t(t)].size());
        s.pool->runWithThread(threads, [&](int, int thread) {
            MissChunk& c = s.miss_chunks[size_t(thread)];
            s.group_shares.drain(thread, kGroupChunk, [&](size_t i0, size_t i1, int owner) {
                for (size_t i = i0; i < i1; ++i) missesOfGroup(s.own_groups[size_t(owner)][i], c, uint32_t(thread));
            });
        });
    }
    else
        for (size_t g = 0; g < G; ++g) missesOfGroup(g, s.miss_chunks[0], 0);

    // 2. The new voxels, in brick-key and slot order (serial: creation order is
    //    part of the map), with their miss.
    for (size_t g = 0; g < G; ++g)
    {
        const Scratch::FreshMisses& fresh = s.fresh_misses[g];
        if (fresh.begin == fresh.end) continue;
        const MissChunk& c = s.miss_chunks[fresh.chunk];
        const uint32_t brick = store_.brickFor(refs[s.miss_groups[g].first].brick_key);
        for (uint32_t e = fresh.begin; e < fresh.end; ++e)
        {
            Voxel& v = store_[store_.findOrCreateInBrick(brick, c.slot[e])];
            v.occ = std::max(log_odds_min, v.occ + c.delta[e]);
        }
    }

    s.frame_bricks = G;
    s.frame_gaussians = 0;
    size_t fresh = 0;
    for (int t = 0; t < threads; ++t)
    {
        st.missed_voxels += s.miss_chunks[size_t(t)].misses;
        s.frame_gaussians += s.miss_chunks[size_t(t)].gaussians;
        fresh += s.miss_chunks[size_t(t)].slot.size();
    }
    // Which thread takes which brick changes from frame to frame: each keeps
    // room for all of them, so that frames like this one do not allocate.
    for (int t = 0; t < threads; ++t)
    {
        if (s.own_groups[size_t(t)].capacity() < G) s.own_groups[size_t(t)].reserve(G);
        MissChunk& c = s.miss_chunks[size_t(t)];
        if (c.slot.capacity() < fresh) c.slot.reserve(fresh);
        if (c.delta.capacity() < fresh) c.delta.reserve(fresh);
    }
}

}  // namespace pndt
