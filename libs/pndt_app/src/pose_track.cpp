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
    // A stampless file's made-up stamps (index / 30 Hz) would be interpolated against the
    // rawlog's real ones: frames skipped or mapped with the poses of other frames.
    if (io::isStampless(format))
        throw std::runtime_error(fmt::format(
            "{}: '{}' pose files hold no stamps, and pndt-map matches poses to frames by time; write them "
            "into the rawlog with pndt-convert --poses {} --pose-format {} (frame i takes pose i), or give a "
            "stamped format (tum, rtabmap1, rtabmap10, rtabmap11, nicr)",
            path, io::toString(format), path, io::toString(format)));
    auto poses = io::readPoseFile(path, format);
    return PoseTrack(std::move(poses), frame.value_or(defaultPoseFrame(format)), max_gap, path);
}

std::optional<Pose> PoseTrack::cameraAt(double t, const mrpt::poses::CPose3D& extrinsic) const
{
    const auto p = interp_.at(t - clock_offset_, max_gap_);
    if (!p) return std::nullopt;
    if (frame_ == PoseFrame::Camera) return *p;
    return cameraPoseInWorld(toMrpt(*p), extrinsic);
}

}  // namespace pndt::app
