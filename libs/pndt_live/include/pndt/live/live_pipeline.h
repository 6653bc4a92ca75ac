// The live pipeline of pndt-live (issue #19): capture -> segmentation -> mapping -> writers.
//
//  - capture (calling run()'s own thread): grabs frames, stamps them, queues them for the
//    segmentation and, in capture order, for the mapper;
//  - segmentation: labels the newest waiting frames; when it falls behind, the oldest frame
//    waiting for it goes on unlabelled (counted) and is mapped geometry-only, so the map keeps
//    up with the camera;
//  - mapping: waits (bounded) for a pose at or after the frame's stamp, records the poses and
//    the frame, interpolates the camera pose and integrates into the short-term maps exactly as
//    pndt-map does with a rawlog's robot poses — so replaying the recording with pndt-map gives
//    the same maps; a frame whose pose does not come in time is skipped and counted, never
//    mapped with a stale pose;
//  - writers: the recording (own thread) and the short-term maps' writer (ShortTermMaps).
#pragma once

#include <pndt/app/pose_refinement.h>
#include <pndt/app/pose_track.h>
#include <pndt/app/short_term_maps.h>
#include <pndt/app/world_up.h>
#include <pndt/live/oni_capture.h>
#include <pndt/live/pose_stream.h>
#include <pndt/mrpt/observation_pairer.h>
#include <pndt/seg/segmenter.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <limits>
#include <memory>
#include <string>

namespace pndt::live
{
/// Where frames come from: an OpenNI2 device (OniCapture, MrptCapture), or a test double.
class FrameGrabber
{
   public:
    virtual ~FrameGrabber() = default;
    virtual std::optional<CapturedFrame> grab(double timeout_s) = 0;
    virtual bool disconnected() const = 0;
    /// Why frames stopped, when the grabber knows better than "disconnected" / "no frame".
    virtual std::string lostReason() const { return {}; }
    /// The pipeline takes no more frames (the device may stop streaming).
    virtual void stopCapture() {}
};
std::unique_ptr<FrameGrabber> grabberOf(OniCapture& c);

struct LiveOptions
{
    double pose_wait = 0.5;        ///< seconds a frame waits for a bracketing pose before it is skipped
    bool device_stamps = true;     ///< frame time = device stamp (+ stamp_offset); false: host clock at grab
    double stamp_offset = 0;       ///< seconds added to device stamps
    double max_pose_gap = 0.1;     ///< as pndt-map's pose_max_gap
    mrpt::poses::CPose3D camera_pose;  ///< robot -> camera (the scans' sensorPose)
    size_t segmentation_queue = 2; ///< frames waiting for the segmentation before the oldest goes on unlabelled
    size_t mapping_queue = 90;     ///< frames waiting for the mapper before capture drops new ones
    /// Seconds the mapper waits for the labels of the frame it is at (the segmentation is
    /// working on it); then the frame is mapped geometry-only and its late labels are dropped.
    double label_wait = 0.25;
    int segmentation_threads = 1;  ///< OpenCV threads of the segmentation (0 = OpenCV's default)
    double grab_timeout = 3.0;     ///< seconds without a frame (or one after the last frame's stamp) = camera lost
    uint64_t max_frames = 0;       ///< stop after this many captured frames (0 = until stopped)
    std::string record;            ///< rawlog of what was seen (empty = none)
    /// Cut the recording into files of this many minutes of sensor time (0 = one file):
    /// rec.rawlog -> rec-0000.rawlog, rec-0001.rawlog, ..., cut between frames.
    double record_minutes = 0;
    /// With record_minutes: keep only the newest record_keep files (0 = all): a black box.
    size_t record_keep = 0;
    /// Interleave what is recorded (poses, scans, labels: what a replay of the recording reads,
    /// in its order) with the maps in the short-term maps' maps.rawlog, as pndt-map's
    /// maps_rawlog_inputs does with its input.
    bool rawlog_inputs = false;
    /// Frame-to-map pose refinement before integration, as pndt-map --refine (null = none).
    app::FramePoseRefinement* refinement = nullptr;
    std::string pose_label = "LIVE_POSE";
};

struct LiveStats
{
    std::atomic<uint64_t> captured{0}, segmented{0}, labelled{0}, seg_dropped{0}, mapping_dropped{0}, mapped{0},
        pose_wait_skipped{0}, no_pose_skipped{0}, recorded_frames{0}, seg_errors{0}, label_late{0},
        stamp_back_dropped{0};  ///< frames not after the frame before (dropped at capture)
    /// The recording, set once run() ends: files opened, of them deleted (record_keep), and
    /// the compressed bytes of those kept.
    std::atomic<uint64_t> recorded_files{0}, recorded_files_deleted{0}, recorded_bytes{0};
    std::atomic<bool> camera_lost{false}, camera_unplugged{false};
    std::string camera_error;  ///< set once before camera_lost
};

class LivePipeline
{
   public:
    /// `segmenter` may be null (geometry only). Everything passed must outlive run().
    LivePipeline(FrameGrabber& grabber, seg::Segmenter* segmenter, LivePoseBuffer& poses, app::ShortTermMaps& maps,
                 const InsertionOptions& pairing, LiveOptions options);
    ~LivePipeline();

    /// Runs until `stop` is set, max_frames were captured or the camera is lost; calls
    /// `status` about once a second from the calling thread. Finalises: remaining frames are
    /// mapped, the maps finished and the recording committed. Rethrows a mapping error.
    void run(const std::atomic<bool>& stop, const std::function<void(const LiveStats&, double seconds)>& status);

    const LiveStats& stats() const { return stats_; }
    /// The last mapped frame (for the final views), if any.
    const std::optional<PairedFrame>& last() const { return last_; }
    /// Pose-track size, for the summary.
    size_t poses() const { return track_.size(); }
    /// The up of the mapped frames' robot poses (their z through the camera's mount), read once
    /// run() has returned: whether the localiser's world is z-up.
    const app::CameraUpTally& cameraUp() const { return camera_up_; }

   private:
    struct Item;
    struct Queues;
    void captureLoop(const std::atomic<bool>& stop);
    void segmentationLoop();
    void mappingLoop();
    void mapItem(Item& it, std::vector<PairedFrame>& done, const std::function<void()>& integrate_done);
    /// Until a stop is asked for: never; then one pose wait later (queued frames stop waiting).
    std::chrono::steady_clock::time_point drainDeadline() const;

    FrameGrabber& grabber_;
    seg::Segmenter* segmenter_;
    LivePoseBuffer& poses_;
    app::ShortTermMaps& maps_;
    ObservationPairer pairer_;
    app::PoseTrack track_;
    LiveOptions o_;
    LiveStats stats_;
    std::optional<PairedFrame> last_;
    app::CameraUpTally camera_up_;  ///< the mapping thread's
    std::atomic<int64_t> drain_deadline_ns_{std::numeric_limits<int64_t>::max()};  ///< steady clock
    bool pose_gap_reported_ = false;
    std::unique_ptr<Queues> q_;
};

}  // namespace pndt::live
