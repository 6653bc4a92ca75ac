#include <fmt/format.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/rawlog_frames.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace pndt
{
RawlogFrameWriter::RawlogFrameWriter(std::string path, std::string rgbd_label, int gz_level)
    : path_(std::move(path)), tmp_(fmt::format("{}.tmp.{}", path_, ::getpid())), label_(std::move(rgbd_label))
{
    out_ = std::make_unique<mrpt::io::CFileGZOutputStream>();
    if (!out_->open(tmp_, gz_level)) throw std::runtime_error(fmt::format("{}: cannot open for writing", tmp_));
}

RawlogFrameWriter::~RawlogFrameWriter()
{
    if (!committed_)
    {
        out_.reset();
        std::remove(tmp_.c_str());
    }
}

void RawlogFrameWriter::writeObservation(const mrpt::obs::CObservation& obs)
{
    auto a = mrpt::serialization::archiveFrom(*out_);
    a << obs;
}

void RawlogFrameWriter::write(const PanopticFrame& f, double t, const std::optional<Pose>& T_world_cam,
                              const Image<std::array<uint8_t, 3>>* rgb, const std::string& pose_label)
{
    const auto stamp = mrpt::Clock::fromDouble(t);
    auto a = mrpt::serialization::archiveFrom(*out_);
    if (T_world_cam)
    {
        mrpt::obs::CObservationRobotPose pose;
        pose.sensorLabel = pose_label;
        pose.timestamp = stamp;
        // Robot pose such that robot ⊕ sensorPose is the camera (MRPT sensor axes).
        pose.pose.mean = mrptSensorPoseOf(*T_world_cam) + (-sensor_pose_);
        a << pose;
    }
    mrpt::obs::CObservation3DRangeScan scan;
    scan.sensorLabel = label_;
    scan.timestamp = stamp;
    scan.sensorPose = sensor_pose_;
    unstored_depth_ += rangeScanFrom(f, scan);
    if (rgb && !rgb->empty())
    {
        scan.hasIntensityImage = true;
        scan.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
        scan.intensityImage.resize(rgb->width, rgb->height, mrpt::img::CH_RGB);
        for (int r = 0; r < rgb->height; ++r)
        {
            uint8_t* row = scan.intensityImage.ptrLine<uint8_t>(r);  // BGR, as OpenCV
            for (int c = 0; c < rgb->width; ++c)
            {
                const auto& px = rgb->at(r, c);
                row[3 * c + 0] = px[2];
                row[3 * c + 1] = px[1];
                row[3 * c + 2] = px[0];
            }
        }
    }
    a << scan;
    if (f.hasLabels())
    {
        mrpt::obs::CObservationImage sem, inst;
        labelImagesFrom(f, label_, stamp, sem, inst);
        a << sem << inst;
    }
    ++frames_;
}

void RawlogFrameWriter::commit()
{
    out_->close();
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) throw std::runtime_error(fmt::format("cannot rename {} to {}: {}", tmp_, path_, ec.message()));
    committed_ = true;
}

}  // namespace pndt
