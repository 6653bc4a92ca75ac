#include <fmt/format.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/system/datetime.h>
#include <pndt/mrpt/observation_frame.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <vector>

namespace pndt
{
std::string describeObservation(const mrpt::obs::CObservation& obs)
{
    return fmt::format("'{}' @ {:.6f}", obs.sensorLabel, mrpt::Clock::toDouble(obs.timestamp));
}

namespace
{
/// Intrinsics of the scan's range image, checked (InputError naming the scan).
CameraIntrinsics rangeIntrinsics(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& who)
{
    obs.load();  // externally stored range images
    if (!obs.hasRangeImage) throw InputError(who + ": range scan without a range image");
    const int H = int(obs.rangeImage.rows()), W = int(obs.rangeImage.cols());
    const auto& cam = obs.cameraParams;
    CameraIntrinsics K;
    K.width = W;
    K.height = H;
    K.fx = cam.fx();
    K.fy = cam.fy();
    K.cx = cam.cx();
    K.cy = cam.cy();
    if (const std::string problem = K.invalidReason(); !problem.empty())
        throw InputError(fmt::format("{}: invalid depth camera intrinsics: {}", who, problem));
    if (int(cam.ncols) != W || int(cam.nrows) != H)
        throw InputError(fmt::format("{}: range image is {}x{} but its camera model is {}x{}", who, W, H, cam.ncols,
                                     cam.nrows));
    if (!(obs.rangeUnits > 0)) throw InputError(fmt::format("{}: rangeUnits must be positive", who));
    return K;
}
}  // namespace

FrameView frameViewOf(const mrpt::obs::CObservation3DRangeScan& obs, std::string& source)
{
    source = describeObservation(obs);
    FrameView v;
    v.K = rangeIntrinsics(obs, source);
    v.source = source;
    const int W = v.K.width, H = v.K.height;
    // MRPT's matrices are row-major; the stride is measured, not assumed.
    const uint16_t* first = &obs.rangeImage(0, 0);
    const size_t stride = H > 1 ? size_t(&obs.rangeImage(1, 0) - first) : size_t(W);
    v.depth = DepthView::units(first, W, H, double(obs.rangeUnits), stride,
                               obs.range_is_depth ? RangeKind::Z : RangeKind::Ray);
    return v;
}

void depthFrameFrom(const mrpt::obs::CObservation3DRangeScan& obs, PanopticFrame& out)
{
    const std::string who = describeObservation(obs);
    const CameraIntrinsics K = rangeIntrinsics(obs, who);
    const int H = K.height, W = K.width;
    out.K = K;
    out.source = who;
    out.depth.reshape(W, H);  // every pixel is written below
    const float units = obs.rangeUnits;
    const uint16_t* first = &obs.rangeImage(0, 0);
    const size_t stride = H > 1 ? size_t(&obs.rangeImage(1, 0) - first) : size_t(W);
    thread_local std::vector<double> xs;  // the columns' ray slopes, for Euclidean ranges (kept: no allocation per frame)
    if (!obs.range_is_depth)
    {
        xs.resize(size_t(W));
        for (int c = 0; c < W; ++c) xs[size_t(c)] = (c - K.cx) / K.fx;
    }
    for (int r = 0; r < H; ++r)
    {
        const uint16_t* in = first + size_t(r) * stride;
        float* row = out.depth.data.data() + size_t(r) * size_t(W);
        for (int c = 0; c < W; ++c) row[c] = float(in[c]) * units;
        if (obs.range_is_depth) continue;
        // Euclidean range along the pixel's ray -> depth along the optical axis. Computed for
        // every pixel and selected (no branch, so the compiler vectorises the square roots);
        // the same expression, so the same bits, as one pixel at a time.
        const double y = (r - K.cy) / K.fy;
        for (int c = 0; c < W; ++c)
        {
            const double x = xs[size_t(c)];
            const float depth = float(row[c] / std::sqrt(1.0 + x * x + y * y));
            row[c] = row[c] > 0 ? depth : row[c];
        }
    }
    // No labels yet; a reused frame keeps the allocations for the next labels.
    out.scores_in_range = false;
    out.semantic.reshape(0, 0);
    out.semantic_score.reshape(0, 0);
    out.instance.reshape(0, 0);
    out.panoptic_score.reshape(0, 0);
}

namespace
{
/// The checks of a label image shared by both decoders (InputError naming the observation).
const mrpt::img::CImage& checkedLabelImage(const mrpt::obs::CObservationImage& obs, int W, int H)
{
    const mrpt::img::CImage& img = obs.image;
    const std::string who = describeObservation(obs);
    if (img.isEmpty()) throw InputError(who + ": empty label image");
    if (img.channelCount() != 1 || img.getPixelDepth() != mrpt::img::PixelDepth::D32F)
        throw InputError(who + ": label image must be single-channel float32 (id + score)");
    if (int(img.getWidth()) != W || int(img.getHeight()) != H)
        throw InputError(fmt::format("{}: label image is {}x{} but the depth image is {}x{}", who, img.getWidth(),
                                     img.getHeight(), W, H));
    return img;
}

/// One row of "id + score" values into ids below `limit` (a power of two <= 2^32) and
/// scores: id = floor(v), score = v - id, as the float operations of design §5 give
/// them. Returns false when a value is not finite, negative or >= limit (those pixels'
/// outputs are then meaningless: the caller reports the first bad one). No branch per
/// pixel, so the compiler vectorises it: floor is the truncation of a value >= 0,
/// taken through int32 (values >= 2^31 are integers and shifted down by 2^31 first).
template <typename Id>
bool decodeRow(const float* in, int n, float limit, Id* ids, float* scores)
{
    uint32_t bad = 0;
    for (int c = 0; c < n; ++c)
    {
        const float v = in[c];
        const bool ok = (v >= 0.f) & (v < limit);  // false for NaN
        bad |= uint32_t(!ok);
        const float safe = ok ? v : 0.f;
        const bool high = safe >= 2147483648.f;
        const float shift = high ? 2147483648.f : 0.f;
        const int32_t low = int32_t(safe - shift);
        ids[c] = Id(uint32_t(low) + (high ? 0x80000000u : 0u));
        scores[c] = safe - (float(low) + shift);
    }
    return bad == 0;
}

/// Throws an InputError naming the first invalid value (not finite, negative or >= 2^32:
/// ids are 32-bit) of a label image and its pixel; returns when there is none.
void throwFirstInvalid(const mrpt::obs::CObservationImage& obs)
{
    const mrpt::img::CImage& img = obs.image;
    for (int r = 0; r < int(img.getHeight()); ++r)
    {
        const float* row = img.ptrLine<float>(r);
        for (int c = 0; c < int(img.getWidth()); ++c)
            if (!(row[c] >= 0.f && row[c] < 4294967296.f))
                throw InputError(fmt::format("{}: invalid id+score value {} at pixel (row {}, col {})",
                                             describeObservation(obs), row[c], r, c));
    }
}

/// The first class id of a semantic image that does not fit 16 bits.
[[noreturn]] void throwFirstWideClass(const mrpt::obs::CObservationImage& obs)
{
    const mrpt::img::CImage& img = obs.image;
    for (int r = 0; r < int(img.getHeight()); ++r)
    {
        const float* row = img.ptrLine<float>(r);
        for (int c = 0; c < int(img.getWidth()); ++c)
            if (row[c] >= 65536.f)
                throw InputError(fmt::format("{}: class id {} does not fit 16 bits", describeObservation(obs),
                                             uint32_t(row[c])));
    }
    throw InputError(describeObservation(obs) + ": class id does not fit 16 bits");  // not reached
}

/// Decodes a whole label image; false when some value is out of [0, limit).
template <typename Id>
bool decodeImage(const mrpt::img::CImage& img, float limit, Image<Id>& ids, Image<float>& scores)
{
    const int W = int(img.getWidth()), H = int(img.getHeight());
    ids.reshape(W, H);  // every pixel is written
    scores.reshape(W, H);
    bool ok = true;
    for (int r = 0; r < H; ++r)  // ptrLine: at<float>() is wrong for 32F in MRPT 2.5
        ok &= decodeRow(img.ptrLine<float>(r), W, limit, ids.data.data() + size_t(r) * size_t(W),
                        scores.data.data() + size_t(r) * size_t(W));
    return ok;
}

/// Ids a float label image carries exactly: below 2^24, where floats stop holding every integer.
constexpr uint32_t kFloatExactIds = 1u << 24;

/// ids + clamped scores (0 where there are none) as "id + score" floats, one row. Above 2^15
/// the float spacing exceeds 0.002, and id + 0.999 rounded up to id + 1: the next id. The
/// sum is kept below id + 1 (the largest float under it), so the id stays exact and only the
/// score's precision falls with the id (1/256 at 65536, 1/2 at 2^22). Returns false if an
/// id is 2^24 or more (nothing written for it is exact). No branch per pixel.
template <typename Id>
bool encodeRow(const Id* ids, const float* scores, int n, float* out)
{
    uint32_t bad = 0;
    for (int c = 0; c < n; ++c)
    {
        const uint32_t id = uint32_t(ids[c]);
        bad |= uint32_t(id >= kFloatExactIds);
        const float base = float(id);
        const float sum = scores ? base + std::clamp(scores[c], 0.f, 0.999f) : base;
        uint32_t below_next;  // the largest float below id + 1 (exact: id + 1 <= 2^24)
        const float next = base + 1.f;
        std::memcpy(&below_next, &next, sizeof below_next);
        below_next -= 1;
        float cap;
        std::memcpy(&cap, &below_next, sizeof cap);
        out[c] = std::min(sum, cap);
    }
    return bad == 0;
}

template <typename Id>
void encodeImage(const Image<Id>& ids, const Image<float>& scores, mrpt::img::CImage& out, const char* what)
{
    out.resize(ids.width, ids.height, mrpt::img::CH_GRAY, mrpt::img::PixelDepth::D32F);
    const size_t W = size_t(ids.width);
    for (int r = 0; r < ids.height; ++r)
        if (!encodeRow(ids.data.data() + r * W, scores.empty() ? nullptr : scores.data.data() + r * W, ids.width,
                       out.ptrLine<float>(r)))
            for (int c = 0; c < ids.width; ++c)
                if (uint32_t(ids.data[r * W + size_t(c)]) >= kFloatExactIds)
                    throw InputError(fmt::format(
                        "{} id {} at pixel (row {}, col {}) does not fit a float label image (\"id + score\", "
                        "exact below 2^24 = 16777216)",
                        what, uint32_t(ids.data[r * W + size_t(c)]), r, c));
}
}  // namespace

void attachPanopticLabels(const mrpt::obs::CObservationImage& semantic, const mrpt::obs::CObservationImage& instance,
                          PanopticFrame& f)
{
    const int W = f.depth.width, H = f.depth.height;
    try
    {
        // Class ids are 16-bit, so a semantic value of 65536 or more fails the fast decode; the
        // slow scans then report the first problem in the order it always was: an invalid
        // semantic value, an invalid instance value, a class id too wide.
        const bool sem_ok = decodeImage(checkedLabelImage(semantic, W, H), 65536.f, f.semantic, f.semantic_score);
        if (!sem_ok) throwFirstInvalid(semantic);  // returns when the classes are only too wide
        if (!decodeImage(checkedLabelImage(instance, W, H), 4294967296.f, f.instance, f.panoptic_score))
        {
            throwFirstInvalid(instance);
            throw InputError(describeObservation(instance) + ": invalid id+score value");  // not reached
        }
        if (!sem_ok) throwFirstWideClass(semantic);
        f.scores_in_range = true;  // fractions of "id + score": in [0, 1) by construction
    }
    catch (...)
    {
        // No half-decoded labels: a caller that goes on maps the frame geometry-only.
        f.scores_in_range = false;
        f.semantic = {};
        f.semantic_score = {};
        f.instance = {};
        f.panoptic_score = {};
        throw;
    }
}

void encodeIdScoreImage(const Image<uint32_t>& ids, const Image<float>& scores, mrpt::img::CImage& out)
{
    encodeImage(ids, scores, out, "label");
}

size_t rangeScanFrom(const PanopticFrame& f, mrpt::obs::CObservation3DRangeScan& o)
{
    const int W = f.depth.width, H = f.depth.height;
    o.hasRangeImage = true;
    o.rangeImage_setSize(H, W);
    o.rangeUnits = 0.001f;
    o.range_is_depth = true;
    float farthest = 0;
    size_t unstored = 0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            const float d = f.depth.at(r, c);
            const bool ok = d > 0 && d < 65.535f;
            const uint16_t mm = ok ? uint16_t(std::lround(d * 1000.f)) : 0;
            o.rangeImage(r, c) = mm;
            unstored += (d > 0 && std::isfinite(d) && mm == 0);  // NaN and inf: no depth to lose
            if (ok) farthest = std::max(farthest, d);
        }
    // MRPT's default is 5 m; tools that honour maxRange must see every sample.
    o.maxRange = std::max(5.0f, std::ceil(farthest));
    o.cameraParams.ncols = W;
    o.cameraParams.nrows = H;
    o.cameraParams.fx(f.K.fx);
    o.cameraParams.fy(f.K.fy);
    o.cameraParams.cx(f.K.cx);
    o.cameraParams.cy(f.K.cy);
    o.cameraParamsIntensity = o.cameraParams;
    return unstored;
}

void labelImagesFrom(const PanopticFrame& f, const std::string& rgbd_label, mrpt::Clock::time_point stamp,
                     mrpt::obs::CObservationImage& sem, mrpt::obs::CObservationImage& inst)
{
    encodeImage(f.semantic, f.semantic_score, sem.image, "class");
    sem.sensorLabel = rgbd_label + "_PANOPTIC_SEMANTIC";
    sem.timestamp = stamp;
    if (f.hasInstances())
        encodeImage(f.instance, f.panoptic_score, inst.image, "instance");
    else
    {
        inst.image.resize(f.depth.width, f.depth.height, mrpt::img::CH_GRAY, mrpt::img::PixelDepth::D32F);
        for (int r = 0; r < f.depth.height; ++r)
        {
            float* row = inst.image.ptrLine<float>(r);
            std::fill(row, row + f.depth.width, 0.f);  // no instance, score 0
        }
    }
    inst.sensorLabel = rgbd_label + "_PANOPTIC_INSTANCE";
    inst.timestamp = stamp;
    for (auto* o : {&sem, &inst})
    {
        o->cameraParams.ncols = f.K.width;
        o->cameraParams.nrows = f.K.height;
        o->cameraParams.fx(f.K.fx);
        o->cameraParams.fy(f.K.fy);
        o->cameraParams.cx(f.K.cx);
        o->cameraParams.cy(f.K.cy);
    }
}

Pose toEigen(const mrpt::poses::CPose3D& p)
{
    const auto m = p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    Pose T;
    T.matrix() = m.asEigen();
    return T;
}

mrpt::poses::CPose3D toMrpt(const Pose& T)
{
    mrpt::math::CMatrixDouble44 m;
    m.asEigen() = T.matrix();
    return mrpt::poses::CPose3D(m);
}

namespace
{
/// Optical axes (x right, y down, z forward) expressed in MRPT's sensor frame.
Pose opticalInSensor()
{
    Pose T = Pose::Identity();
    T.linear() << 0, 0, 1,  //
        -1, 0, 0,           //
        0, -1, 0;
    return T;
}
}  // namespace

Pose cameraPoseInWorld(const mrpt::poses::CPose3D& robotPose, const mrpt::poses::CPose3D& sensorPose)
{
    return toEigen(robotPose) * toEigen(sensorPose) * opticalInSensor();
}

mrpt::poses::CPose3D mrptSensorPoseOf(const Pose& T_world_cam) { return toMrpt(T_world_cam * opticalInSensor().inverse()); }

}  // namespace pndt
