#include <mrpt/system/datetime.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/observation_pairer.h>

#include <cmath>

using mrpt::obs::CObservation3DRangeScan;
using mrpt::obs::CObservationImage;

namespace pndt
{
void ObservationPairer::clear()
{
    pending_.reset();
    spare_.reset();
    spare_labels_ = {};
    labels_.clear();
    dropped_ = 0;
}

bool ObservationPairer::push(const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& robotPose,
                             std::vector<PairedFrame>& done)
{
    if (IS_CLASS(obs, CObservation3DRangeScan))
    {
        const auto& scan = static_cast<const CObservation3DRangeScan&>(obs);
        return pushScan(scan, cameraPoseInWorld(robotPose, scan.sensorPose), done);
    }
    if (IS_CLASS(obs, CObservationImage)) return pushLabelImage(static_cast<const CObservationImage&>(obs), done);
    return false;
}

bool ObservationPairer::pushScan(const CObservation3DRangeScan& scan, const Pose& T_world_cam,
                                 std::vector<PairedFrame>& done)
{
    if (!scan.hasRangeImage) return false;
    flush(done);  // the previous frame's labels did not come: geometry only
    PairedFrame p = spare_ ? std::move(*spare_) : PairedFrame{};
    spare_.reset();
    depthFrameFrom(scan, p.frame);  // sets every field of the frame anew; a throw leaves nothing pending
    p.T_world_cam = T_world_cam;
    p.stamp = scan.timestamp;
    p.label = scan.sensorLabel;
    p.labelled = false;
    pending_ = std::move(p);
    tryComplete(done);
    return true;
}

void ObservationPairer::recycle(PairedFrame&& used)
{
    if (used.frame.hasLabels()) spare_labels_.takeFrom(used.frame);
    spare_ = std::move(used);
}

bool ObservationPairer::pushLabelImage(const CObservationImage& obs, std::vector<PairedFrame>& done)
{
    const auto endsWith = [](const std::string& s, const std::string& suffix) {
        return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    BufferedLabel b;
    if (endsWith(obs.sensorLabel, options.semantic_suffix))
        b.rgbd_label = obs.sensorLabel.substr(0, obs.sensorLabel.size() - options.semantic_suffix.size());
    else if (endsWith(obs.sensorLabel, options.instance_suffix))
    {
        b.semantic = false;
        b.rgbd_label = obs.sensorLabel.substr(0, obs.sensorLabel.size() - options.instance_suffix.size());
    }
    else
        return false;  // an ordinary camera image: not ours
    if (obs.image.channelCount() != 1 || obs.image.getPixelDepth() != mrpt::img::PixelDepth::D32F)
        throw InputError(describeObservation(obs) + ": panoptic label image must be single-channel float32");
    b.image = std::make_shared<CObservationImage>(obs);
    labels_.push_back(std::move(b));
    while (labels_.size() > options.max_buffered_labels)
    {
        labels_.pop_front();
        ++dropped_;
    }
    tryComplete(done);
    return true;
}

void ObservationPairer::tryComplete(std::vector<PairedFrame>& done)
{
    if (!pending_) return;
    const double t = mrpt::Clock::toDouble(pending_->stamp);
    const double tol = options.label_pairing_tolerance;
    int sem = -1, inst = -1;
    double best_sem = tol, best_inst = tol;
    for (size_t i = 0; i < labels_.size(); ++i)
    {
        const BufferedLabel& b = labels_[i];
        if (b.rgbd_label != pending_->label) continue;
        const double dt = std::abs(mrpt::Clock::toDouble(b.image->timestamp) - t);
        double& best = b.semantic ? best_sem : best_inst;
        if (dt <= best)
        {
            best = dt;
            (b.semantic ? sem : inst) = int(i);
        }
    }
    if (sem < 0 || inst < 0) return;
    spare_labels_.giveTo(pending_->frame);  // decoded in place, no fill
    attachPanopticLabels(*labels_[size_t(sem)].image, *labels_[size_t(inst)].image, pending_->frame);
    labels_.erase(labels_.begin() + std::max(sem, inst));
    labels_.erase(labels_.begin() + std::min(sem, inst));
    // Older label images of this sensor can no longer meet a depth frame.
    for (auto it = labels_.begin(); it != labels_.end();)
        if (it->rgbd_label == pending_->label && mrpt::Clock::toDouble(it->image->timestamp) < t - tol)
        {
            it = labels_.erase(it);
            ++dropped_;
        }
        else
            ++it;
    pending_->labelled = true;
    done.push_back(std::move(*pending_));
    pending_.reset();
}

void ObservationPairer::flush(std::vector<PairedFrame>& done)
{
    if (!pending_) return;
    done.push_back(std::move(*pending_));
    pending_.reset();
}

}  // namespace pndt
