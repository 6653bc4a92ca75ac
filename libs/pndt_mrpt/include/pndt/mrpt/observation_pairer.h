// Pairs each CObservation3DRangeScan with its two float32 panoptic label images
// (design §5), which may arrive before or after it.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/frame.h>
#include <pndt/mrpt/label_image_stash.h>

#include <deque>
#include <optional>
#include <vector>

namespace pndt
{
/// How observations are paired into frames.
struct InsertionOptions : public mrpt::config::CLoadableOptions
{
    double label_pairing_tolerance = 0.01;  ///< seconds between depth and label stamps
    std::string semantic_suffix = "_PANOPTIC_SEMANTIC";
    std::string instance_suffix = "_PANOPTIC_INSTANCE";
    size_t max_buffered_labels = 16;  ///< label images kept while waiting for depth
    /// Register each frame to the map before integrating it (pndt_refine, doc/refinement.md;
    /// RefineOptions defaults, these two overridable). Not saved with the map.
    bool refine_pose = false;
    double refine_thing_weight = 0.5;
    double refine_loss_scale = 1.0;

    void loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& section) override;
    void dumpToTextStream(std::ostream& out) const override;
};

/// A depth frame ready to integrate, with or without labels.
struct PairedFrame
{
    PanopticFrame frame;
    Pose T_world_cam = Pose::Identity();
    mrpt::Clock::time_point stamp;
    std::string label;  ///< the range scan's sensor label
    bool labelled = false;
};

class ObservationPairer
{
   public:
    InsertionOptions options;

    ObservationPairer() = default;
    /// A copy pairs as the original does; it does not take the spare frame (megabytes).
    ObservationPairer(const ObservationPairer& o)
        : options(o.options), pending_(o.pending_), labels_(o.labels_), dropped_(o.dropped_)
    {
    }
    ObservationPairer& operator=(const ObservationPairer& o)
    {
        options = o.options;
        pending_ = o.pending_;
        labels_ = o.labels_;
        dropped_ = o.dropped_;
        spare_.reset();
        spare_labels_ = {};
        return *this;
    }
    ObservationPairer(ObservationPairer&&) = default;
    ObservationPairer& operator=(ObservationPairer&&) = default;

    /// Feeds one observation; frames it completes are appended to `done` (a
    /// geometry-only frame whose labels never came, and/or a labelled frame).
    /// `robotPose` is used for range scans only. Returns false for observations
    /// that are neither range scans nor our label images. Throws InputError for
    /// malformed label images (naming the observation).
    bool push(const mrpt::obs::CObservation& obs, const mrpt::poses::CPose3D& robotPose,
              std::vector<PairedFrame>& done);
    /// Same, with the optical camera pose already known (skips robot ⊕ sensorPose).
    bool pushScan(const mrpt::obs::CObservation3DRangeScan& scan, const Pose& T_world_cam,
                  std::vector<PairedFrame>& done);
    /// Releases the depth frame still waiting for labels, geometry only.
    void flush(std::vector<PairedFrame>& done);
    /// Hands back a frame the caller is done with: the next scan is converted into its
    /// images (no allocation, no page faults per frame on a long run). One is kept.
    /// Its label images are kept apart at their size until a labelled frame takes
    /// them: a scan starts without labels, and images grown from empty are zero-filled.
    void recycle(PairedFrame&& used);

    bool hasPending() const { return pending_.has_value(); }
    uint64_t labelImagesDropped() const { return dropped_; }
    /// Label images still waiting for a depth frame.
    size_t labelImagesWaiting() const { return labels_.size(); }
    void clear();

   private:
    bool pushLabelImage(const mrpt::obs::CObservationImage& obs, std::vector<PairedFrame>& done);
    void tryComplete(std::vector<PairedFrame>& done);

    struct BufferedLabel
    {
        mrpt::obs::CObservationImage::Ptr image;
        bool semantic = true;  ///< false: instance image
        std::string rgbd_label;
    };
    std::optional<PairedFrame> pending_;
    std::deque<BufferedLabel> labels_;
    uint64_t dropped_ = 0;
    std::optional<PairedFrame> spare_;  ///< see recycle(); not copied
    LabelImageStash spare_labels_;  ///< see recycle(); not copied
};

}  // namespace pndt
