#include <fmt/format.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/system/datetime.h>
#include <pndt/app/pose_track.h>
#include <pndt/mrpt/observation_frame.h>

namespace pndt::app
{
PoseFrame parsePoseFrame(const std::string& s)
{
    if (s == "robot") return PoseFrame::Robot;
    if (s == "camera") return PoseFrame::Camera;
    throw std::invalid_argument(fmt::format("pose frame '{}' is not robot or camera", s));
}

PoseFrame defaultPoseFrame(io::PoseFormat f)
{
    switch (f)
    {
        case io::PoseFormat::Tum:
        case io::PoseFormat::Kitti:
        case io::PoseFormat::Redwood:
        case io::PoseFormat::Nicr: return PoseFrame::Camera;
        default: return PoseFrame::Robot;
    }
}

namespace
{
io::PoseInterpolator makeInterpolator(std::vector<io::StampedPose> poses, const std::string& source)
{
    if (poses.empty()) throw std::runtime_error(fmt::format("{}: no poses", source));
    try
    {
        return io::PoseInterpolator(std::move(poses));
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(fmt::format("{}: {}", source, e.what()));
    }
}
}  // namespace

PoseTrack::PoseTrack(std::vector<io::StampedPose> poses, PoseFrame frame, double max_gap, std::string source)
    : interp_(makeInterpolator(std::move(poses), source)), frame_(frame), max_gap_(max_gap), source_(std::move(source))
{
}

PoseTrack::PoseTrack(PoseFrame frame, double max_gap, std::string source, std::string label)
    : label_(std::move(label)), frame_(frame), max_gap_(max_gap), source_(std::move(source))
{
}

PoseTrack PoseTrack::whileReading(const std::string& rawlog, const std::string& label, double max_gap)
{
    return PoseTrack(PoseFrame::Robot, max_gap, rawlog, label);
}

bool PoseTrack::addRobotPose(const mrpt::obs::CObservationRobotPose& p)
{
    if (!label_.empty() && p.sensorLabel != label_) return false;
    io::StampedPose sp;
    sp.t = mrpt::Clock::toDouble(p.timestamp);
    sp.T_world_sensor = toEigen(p.pose.mean);
    if (!interp_.empty() && sp.t <= interp_.endTime())
        throw std::runtime_error(fmt::format(
            "{}: robot pose '{}' #{} at t={:.6f} is not after the previous one (t={:.6f}): poses out of order",
            source_, p.sensorLabel, interp_.appended() + 1, sp.t, interp_.endTime()));
    interp_.append(sp);
    return true;
}

PoseTrack PoseTrack::fromFile(const std::string& path, io::PoseFormat format, std::optional<PoseFrame> frame,
                              double max_gap)
{
    // A stampless file's made-up stamps (index / 30 Hz) were interpolated against the frames'
    // real ones: frames skipped, or mapped with the poses of other frames. Its poses go by index.
    if (io::isStampless(format))
    {
        io::PoseReadOptions ro;
        ro.frame_rate_hz = 1.0;  // t = the pose's index (non-finite poses skipped keep their place)
        const auto poses = io::readPoseFile(path, format, ro);
        if (poses.empty()) throw std::runtime_error(fmt::format("{}: no poses", path));
        PoseTrack track(frame.value_or(defaultPoseFrame(format)), max_gap, path, std::string());
        track.by_index_ = true;
        for (const auto& p : poses)
        {
            const size_t k = size_t(std::llround(p.t));
            if (track.indexed_.size() <= k) track.indexed_.resize(k + 1);
            track.indexed_[k] = p.T_world_sensor;
        }
        track.indexed_size_ = poses.size();
        return track;
    }
    auto poses = io::readPoseFile(path, format);
    return PoseTrack(std::move(poses), frame.value_or(defaultPoseFrame(format)), max_gap, path);
}

std::optional<Pose> PoseTrack::toCamera(const Pose& p, const mrpt::poses::CPose3D& extrinsic) const
{
    if (frame_ == PoseFrame::Camera) return p;
    return cameraPoseInWorld(toMrpt(p), extrinsic);
}

std::optional<Pose> PoseTrack::cameraAt(double t, const mrpt::poses::CPose3D& extrinsic) const
{
    if (by_index_) throw std::logic_error("PoseTrack::cameraAt on a track by index");
    const auto p = interp_.at(t - clock_offset_, max_gap_);
    if (!p) return std::nullopt;
    return toCamera(*p, extrinsic);
}

std::optional<Pose> PoseTrack::cameraAtIndex(size_t k, const mrpt::poses::CPose3D& extrinsic) const
{
    if (!by_index_) throw std::logic_error("PoseTrack::cameraAtIndex on a track by time");
    if (k >= indexed_.size() || !indexed_[k]) return std::nullopt;
    return toCamera(*indexed_[k], extrinsic);
}

}  // namespace pndt::app
