#include <fmt/format.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <pndt/app/rawlog_sequence.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace pndt::app
{
RawlogSequence::RawlogSequence(std::vector<std::string> paths) : paths_(std::move(paths))
{
    if (paths_.empty()) throw std::invalid_argument("RawlogSequence: no file given");
    for (const auto& p : paths_)
    {
        if (!std::filesystem::is_regular_file(p)) throw std::runtime_error(fmt::format("{}: no such file", p));
        if (!std::ifstream(p)) throw std::runtime_error(fmt::format("{}: cannot be opened for reading", p));
        std::error_code ec;
        const auto size = std::filesystem::file_size(p, ec);
        sizes_.push_back(ec ? 0 : size);
        total_bytes_ += sizes_.back();
    }
    in_ = std::make_unique<ObservationStream>(paths_[0]);
}

RawlogSequence::~RawlogSequence() = default;

mrpt::obs::CObservation::Ptr RawlogSequence::next()
{
    for (;;)
    {
        auto obs = in_->next();
        if (!obs)
        {
            if (in_->truncated() || current_ + 1 == paths_.size()) return nullptr;
            bytes_before_ += sizes_[current_];
            in_ = std::make_unique<ObservationStream>(paths_[++current_]);
            scan_seen_in_file_ = false;
            pose_t_before_file_ = last_pose_t_;
            continue;
        }
        if (const auto* pose = dynamic_cast<const mrpt::obs::CObservationRobotPose*>(obs.get()))
        {
            const double t = mrpt::Clock::toDouble(pose->timestamp);
            if (t <= pose_t_before_file_) continue;  // repeated from an earlier file
            last_pose_t_ = std::max(last_pose_t_, t);
        }
        if (const auto* scan = dynamic_cast<const mrpt::obs::CObservation3DRangeScan*>(obs.get()))
        {
            const double t = mrpt::Clock::toDouble(scan->timestamp);
            if (!scan_seen_in_file_ && t <= last_scan_t_)
                throw std::runtime_error(fmt::format(
                    "{}: its first depth frame (t={:.3f} s) is not later than the last one of {} (t={:.3f} s): give "
                    "the files in time order, each once",
                    paths_[current_], t, last_scan_file_, last_scan_t_));
            scan_seen_in_file_ = true;
            last_scan_t_ = std::max(last_scan_t_, t);
            last_scan_file_ = paths_[current_];
        }
        return obs;
    }
}

bool RawlogSequence::truncated() const { return in_->truncated(); }

const std::string& RawlogSequence::stopReason() const { return in_->stopReason(); }

double RawlogSequence::progress() const
{
    if (total_bytes_ == 0) return 1.0;
    const double in_file = in_->progress() * double(sizes_[current_]);
    return std::min(1.0, (double(bytes_before_) + in_file) / double(total_bytes_));
}

}  // namespace pndt::app
