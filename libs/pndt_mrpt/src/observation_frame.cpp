#include <fmt/format.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/system/datetime.h>
#include <pndt/mrpt/observation_frame.h>

#include <algorithm>
#include <cmath>

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
    if (!K.valid() || !std::isfinite(K.fx) || !std::isfinite(K.cx))
        throw InputError(fmt::format("{}: invalid depth camera intrinsics (fx={}, fy={})", who, K.fx, K.fy));
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
    out.depth.resize(W, H, 0.f);
    const float units = obs.rangeUnits;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            float d = float(obs.rangeImage(r, c)) * units;
            if (!obs.range_is_depth && d > 0)
            {
                // Euclidean range along the pixel's ray -> depth along the optical axis.
                const double x = (c - K.cx) / K.fx, y = (r - K.cy) / K.fy;
                d = float(d / std::sqrt(1.0 + x * x + y * y));
            }
            out.depth.at(r, c) = d;
        }
    out.semantic = {};
    out.semantic_score = {};
    out.instance = {};
    out.panoptic_score = {};
}

namespace
{
void decodeIdScore(const mrpt::obs::CObservationImage& obs, int W, int H, Image<uint32_t>& ids, Image<float>& scores)
{
    const std::string who = describeObservation(obs);
    const mrpt::img::CImage& img = obs.image;
    if (img.isEmpty()) throw InputError(who + ": empty label image");
    if (img.channelCount() != 1 || img.getPixelDepth() != mrpt::img::PixelDepth::D32F)
        throw InputError(who + ": label image must be single-channel float32 (id + score)");
    if (int(img.getWidth()) != W || int(img.getHeight()) != H)
        throw InputError(fmt::format("{}: label image is {}x{} but the depth image is {}x{}", who, img.getWidth(),
                                     img.getHeight(), W, H));
    ids.resize(W, H, 0);
    scores.resize(W, H, 0.f);
    for (int r = 0; r < H; ++r)
    {
        const float* row = img.ptrLine<float>(r);  // at<float>() is wrong for 32F in MRPT 2.5
        for (int c = 0; c < W; ++c)
        {
            const float v = row[c];
            // (ids are 32-bit: a larger value would overflow the conversion below)
            if (!std::isfinite(v) || v < 0.f || v >= 4294967296.f)
                throw InputError(fmt::format("{}: invalid id+score value {} at pixel (row {}, col {})", who, v, r, c));
            const float id = std::floor(v);
            ids.at(r, c) = uint32_t(id);
            scores.at(r, c) = v - id;
        }
    }
}
}  // namespace

void attachPanopticLabels(const mrpt::obs::CObservationImage& semantic, const mrpt::obs::CObservationImage& instance,
                          PanopticFrame& f)
{
    Image<uint32_t> sem_ids;
    decodeIdScore(semantic, f.depth.width, f.depth.height, sem_ids, f.semantic_score);
    decodeIdScore(instance, f.depth.width, f.depth.height, f.instance, f.panoptic_score);
    f.semantic.resize(f.depth.width, f.depth.height, 0);
    for (size_t i = 0; i < sem_ids.data.size(); ++i)
    {
        if (sem_ids.data[i] > 0xFFFF)
            throw InputError(fmt::format("{}: class id {} does not fit 16 bits", describeObservation(semantic),
                                         sem_ids.data[i]));
        f.semantic.data[i] = uint16_t(sem_ids.data[i]);
    }
}

void encodeIdScoreImage(const Image<uint32_t>& ids, const Image<float>& scores, mrpt::img::CImage& out)
{
    out.resize(ids.width, ids.height, mrpt::img::CH_GRAY, mrpt::img::PixelDepth::D32F);
    for (int r = 0; r < ids.height; ++r)
    {
        float* row = out.ptrLine<float>(r);
        for (int c = 0; c < ids.width; ++c)
        {
            const float s = scores.empty() ? 0.f : std::clamp(scores.at(r, c), 0.f, 0.999f);
            row[c] = float(ids.at(r, c)) + s;
        }
    }
}

void rangeScanFrom(const PanopticFrame& f, mrpt::obs::CObservation3DRangeScan& o)
{
    const int W = f.depth.width, H = f.depth.height;
    o.hasRangeImage = true;
    o.rangeImage_setSize(H, W);
    o.rangeUnits = 0.001f;
    o.range_is_depth = true;
    float farthest = 0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
        {
            const float d = f.depth.at(r, c);
            const bool ok = d > 0 && d < 65.535f;
            o.rangeImage(r, c) = ok ? uint16_t(std::lround(d * 1000.f)) : 0;
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
}

void labelImagesFrom(const PanopticFrame& f, const std::string& rgbd_label, mrpt::Clock::time_point stamp,
                     mrpt::obs::CObservationImage& sem, mrpt::obs::CObservationImage& inst)
{
    Image<uint32_t> ids(f.semantic.width, f.semantic.height);
    for (size_t i = 0; i < ids.data.size(); ++i) ids.data[i] = f.semantic.data[i];
    encodeIdScoreImage(ids, f.semantic_score, sem.image);
    sem.sensorLabel = rgbd_label + "_PANOPTIC_SEMANTIC";
    sem.timestamp = stamp;
    if (f.hasInstances())
        encodeIdScoreImage(f.instance, f.panoptic_score, inst.image);
    else
        encodeIdScoreImage(Image<uint32_t>(f.depth.width, f.depth.height, 0), {}, inst.image);
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
