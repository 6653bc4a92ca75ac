#include <fmt/format.h>
#include <mrpt/system/datetime.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <pndt/app/gz_rawlog_file.h>
#include <pndt/app/map_rawlog.h>
#include <pndt/live/live_pipeline.h>
#include <pndt/live/stamp_order.h>
#include <pndt/mrpt/observation_frame.h>
#include <pndt/mrpt/rawlog_frames.h>

#include "recorder.h"

#include <opencv2/core/utility.hpp>

#include <atomic>
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

namespace pndt::live
{
namespace
{
class OniGrabber : public FrameGrabber
{
   public:
    explicit OniGrabber(OniCapture& c) : c_(c) {}
    std::optional<CapturedFrame> grab(double t) override { return c_.grab(t); }
    bool disconnected() const override { return c_.disconnected(); }

   private:
    OniCapture& c_;
};

}  // namespace

std::unique_ptr<FrameGrabber> grabberOf(OniCapture& c) { return std::make_unique<OniGrabber>(c); }

struct LivePipeline::Item
{
    CapturedFrame frame;
    double t = 0;
    std::chrono::steady_clock::time_point captured;  ///< its pose wait runs from here
    mrpt::obs::CObservationImage::Ptr semantic, instance;  ///< null: geometry only
    bool ready = false;                                      ///< segmentation done or given up
    bool abandoned = false;  ///< the mapper went on without this frame's labels
};

struct LivePipeline::Queues
{
    std::mutex m;
    std::condition_variable cv;
    std::deque<std::shared_ptr<Item>> to_segment, to_map;
    bool capture_done = false, seg_done = false;
    bool map_done = false;  ///< the mapper has finished its last frame (not only taken it off the queue)
    std::unique_ptr<Recorder> recorder;
    std::exception_ptr map_error;
};

LivePipeline::LivePipeline(FrameGrabber& grabber, seg::Segmenter* segmenter, LivePoseBuffer& poses,
                           app::ShortTermMaps& maps, const InsertionOptions& pairing, LiveOptions options)
    : grabber_(grabber),
      segmenter_(segmenter),
      poses_(poses),
      maps_(maps),
      track_(app::PoseTrack::whileReading("the live pose stream", options.pose_label, options.max_pose_gap)),
      o_(std::move(options)),
      q_(std::make_unique<Queues>())
{
    pairer_.options = pairing;
    if (!o_.record.empty())
        q_->recorder = std::make_unique<Recorder>(RecorderOptions{o_.record, o_.record_minutes * 60, o_.record_keep});
}

LivePipeline::~LivePipeline() = default;

void LivePipeline::captureLoop(const std::atomic<bool>& stop)
{
    // Frames must come in time order (StampOrder says why and how it is checked).
    StampOrder order(o_.device_stamps, o_.grab_timeout);
    const auto seconds = [](std::chrono::steady_clock::time_point p) {
        return std::chrono::duration<double>(p.time_since_epoch()).count();
    };
    while (!stop && (o_.max_frames == 0 || stats_.captured < o_.max_frames))
    {
        auto f = grabber_.grab(o_.grab_timeout);
        if (!f)
        {
            if (stop) break;
            stats_.camera_unplugged = grabber_.disconnected();
            const std::string reason = grabber_.lostReason();
            stats_.camera_error = stats_.camera_unplugged ? std::string("the camera was disconnected")
                                  : !reason.empty()       ? reason
                                                          : fmt::format("no frame from the camera for {:.1f} s", o_.grab_timeout);
            stats_.camera_lost = true;
            break;
        }
        ++stats_.captured;
        auto it = std::make_shared<Item>();
        it->captured = std::chrono::steady_clock::now();
        it->t = o_.device_stamps ? f->device_t + o_.stamp_offset
                                 : mrpt::Clock::toDouble(mrpt::Clock::now());
        f->scan->timestamp = mrpt::Clock::fromDouble(it->t);
        it->t = mrpt::Clock::toDouble(f->scan->timestamp);  // what a replay reads back (100 ns ticks)
        const StampOrder::Verdict verdict = order.next(it->t, seconds(it->captured));
        if (verdict == StampOrder::Verdict::clock_reset)
        {
            ++stats_.stamp_back_dropped;
            stats_.camera_error = order.message();
            stats_.camera_lost = true;
            break;
        }
        if (!order.message().empty()) fmt::print(stderr, "\npndt-live: {}\n", order.message());
        if (verdict == StampOrder::Verdict::drop)
        {
            ++stats_.stamp_back_dropped;
            continue;
        }
        f->scan->sensorPose = o_.camera_pose;
        it->frame = std::move(*f);
        {
            std::lock_guard<std::mutex> lk(q_->m);
            if (q_->to_map.size() >= o_.mapping_queue)
            {
                ++stats_.mapping_dropped;  // the mapper is behind: this frame is not mapped
                continue;
            }
            q_->to_map.push_back(it);
            if (segmenter_)
            {
                q_->to_segment.push_back(it);
                if (q_->to_segment.size() > o_.segmentation_queue)
                {
                    q_->to_segment.front()->ready = true;  // goes on unlabelled: geometry only
                    q_->to_segment.pop_front();
                    if (stats_.seg_dropped++ == 0)
                        fmt::print(stderr,
                                   "\npndt-live: the segmentation is behind the camera: the oldest waiting frame goes "
                                   "on unlabelled and is mapped geometry-only (counted as dropped)\n");
                }
            }
            else
                it->ready = true;
        }
        q_->cv.notify_all();
    }
    grabber_.stopCapture();
    {
        std::lock_guard<std::mutex> lk(q_->m);
        q_->capture_done = true;
    }
    q_->cv.notify_all();
}

void LivePipeline::segmentationLoop()
{
    PanopticFrame frame;
    LabelImageStash labels;  // the segmenter rewrites last frame's label images in place
    Image<seg::RgbPixel> rgb;
    for (;;)
    {
        std::shared_ptr<Item> it;
        {
            std::unique_lock<std::mutex> lk(q_->m);
            q_->cv.wait(lk, [&] { return !q_->to_segment.empty() || q_->capture_done; });
            if (q_->to_segment.empty()) break;
            it = q_->to_segment.front();
            q_->to_segment.pop_front();
            if (it->abandoned) continue;  // already mapped geometry-only
        }
        const auto& scan = *it->frame.scan;
        mrpt::obs::CObservationImage::Ptr sem, inst;
        try
        {
            labels.takeFrom(frame);  // depthFrameFrom would empty them
            depthFrameFrom(scan, frame);
            labels.giveTo(frame);
            seg::SegmentationInput in;
            in.K = frame.K;
            in.depth = &frame.depth;
            if (scan.hasIntensityImage)
            {
                rgb.reshape(int(scan.intensityImage.getWidth()), int(scan.intensityImage.getHeight()));
                for (int r = 0; r < rgb.height; ++r)
                {
                    const uint8_t* row = scan.intensityImage.ptrLine<uint8_t>(r);
                    for (int c = 0; c < rgb.width; ++c) rgb.at(r, c) = {row[3 * c + 2], row[3 * c + 1], row[3 * c]};
                }
                in.color = &rgb;
            }
            in.source = describeObservation(scan);
            segmenter_->segment(in, frame);
            sem = std::make_shared<mrpt::obs::CObservationImage>();
            inst = std::make_shared<mrpt::obs::CObservationImage>();
            labelImagesFrom(frame, scan.sensorLabel, scan.timestamp, *sem, *inst);
        }
        catch (const std::exception& e)
        {
            sem.reset();
            if (stats_.seg_errors++ < 3) fmt::print(stderr, "\npndt-live: segmentation failed: {}\n", e.what());
        }
        ++stats_.segmented;
        {
            std::lock_guard<std::mutex> lk(q_->m);
            if (sem && !it->abandoned)
            {
                it->semantic = std::move(sem);
                it->instance = std::move(inst);
                ++stats_.labelled;
            }
            it->ready = true;
        }
        q_->cv.notify_all();
    }
    {
        std::lock_guard<std::mutex> lk(q_->m);
        q_->seg_done = true;
    }
    q_->cv.notify_all();
}

std::chrono::steady_clock::time_point LivePipeline::drainDeadline() const
{
    return std::chrono::steady_clock::time_point(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::nanoseconds(drain_deadline_ns_.load())));
}

void LivePipeline::mapItem(Item& it, std::vector<PairedFrame>& done, const std::function<void()>& integrate_done)
{
    // Never mapped with a stale pose: wait (bounded) for a pose at or after the frame. The
    // wait counts from the frame's capture (time in the queue included) and ends at the drain
    // deadline once a stop is asked for: frames queued during a localiser outage no longer
    // wait one after another (90 frames x 0.5 s = 45 s before Ctrl-C took effect).
    const auto deadline = std::min(it.captured + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                     std::chrono::duration<double>(std::clamp(o_.pose_wait, 0.0, 1e6))),
                                   drainDeadline());
    const double wait = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (!poses_.waitFor(it.t, std::max(0.0, wait)))
    {
        if (!pose_gap_reported_)
            fmt::print(stderr,
                       "\npndt-live: no pose at or after t={:.4f} s within {} s (newest pose: {}, {} localiser "
                       "connection(s)): frames are skipped and counted until poses come again\n",
                       it.t, o_.pose_wait,
                       poses_.received() ? fmt::format("t={:.4f} s", poses_.latest()) : std::string("none yet"),
                       poses_.open_connections.load());
        pose_gap_reported_ = true;
        ++stats_.pose_wait_skipped;
        return;
    }
    if (pose_gap_reported_) fmt::print(stderr, "\npndt-live: poses again at t={:.3f} s\n", it.t);
    pose_gap_reported_ = false;
    // What is recorded goes, in the same order, into maps.rawlog when inputs are interleaved:
    // the order a replay of the recording reads them.
    const auto emit = [&](const mrpt::obs::CObservation::Ptr& o) {
        if (q_->recorder) q_->recorder->push(o);
        if (o_.rawlog_inputs && maps_.rawlog()) maps_.rawlog()->addInput(o);
    };
    if (q_->recorder) q_->recorder->startFrame(it.t);  // a recording cut into files ends only between frames
    for (auto& p : poses_.take())
    {
        emit(p);
        track_.addRobotPose(*p);
    }
    const auto T = track_.cameraAt(it.t, it.frame.scan->sensorPose);
    if (!T)
    {
        ++stats_.no_pose_skipped;
        return;
    }
    track_.forgetBefore(it.t - app::PoseTrack::kKeptSeconds);  // as pndt-map's replay of the recording
    // The track holds robot poses (a camera-frame stream's in MRPT sensor axes): up is their z.
    camera_up_.add(*T, app::robotUpInCamera(it.frame.scan->sensorPose));
    // Each observation is emitted, paired and what it completes integrated before the next
    // one, as pndt-map does when it replays the recording: a hand-over (a map added to
    // maps.rawlog) then falls between the same inputs in both files. (Emitting the label
    // images before the scan completed the frame before put them ahead of the map in live
    // runs where the previous frame went unlabelled.)
    emit(it.frame.scan);
    pairer_.pushScan(*it.frame.scan, *T, done);
    integrate_done();
    if (it.semantic)
    {
        emit(it.semantic);
        pairer_.push(*it.semantic, mrpt::poses::CPose3D(), done);
        integrate_done();
        emit(it.instance);
        pairer_.push(*it.instance, mrpt::poses::CPose3D(), done);
        integrate_done();
    }
}

void LivePipeline::mappingLoop()
{
    std::vector<PairedFrame> done;
    const auto integrateDone = [&] {
        for (PairedFrame& p : done)
        {
            const double t = mrpt::Clock::toDouble(p.stamp);
            if (o_.refinement)
                p.T_world_cam = o_.refinement->refine(maps_.current() ? &maps_.current()->core() : nullptr, p.frame,
                                                      p.T_world_cam, t);
            maps_.integrate(p.frame, p.T_world_cam, t);
            ++stats_.mapped;
            if (last_) pairer_.recycle(std::move(*last_));  // its images take the next scan
            last_ = std::move(p);
        }
        done.clear();
    };
    try
    {
        for (;;)
        {
            std::shared_ptr<Item> it;
            {
                std::unique_lock<std::mutex> lk(q_->m);
                const auto waitable = [&] {
                    return (!q_->to_map.empty() && q_->to_map.front()->ready) || (q_->to_map.empty() && q_->capture_done);
                };
                q_->cv.wait(lk, [&] { return waitable() || !q_->to_map.empty(); });
                if (!waitable() &&
                    !q_->cv.wait_for(lk, std::chrono::duration<double>(o_.label_wait), waitable))
                {
                    // The segmentation is still on this frame: map it geometry-only now.
                    auto& head = *q_->to_map.front();
                    head.abandoned = head.ready = true;
                    if (stats_.label_late++ == 0)
                        fmt::print(stderr,
                                   "\npndt-live: the segmentation is slower than the camera: frames it cannot label "
                                   "within {} s are mapped geometry-only (counted)\n",
                                   o_.label_wait);
                }
                if (q_->to_map.empty()) break;
                it = q_->to_map.front();
                q_->to_map.pop_front();
            }
            mapItem(*it, done, integrateDone);
            integrateDone();
        }
        pairer_.flush(done);
        integrateDone();
    }
    catch (...)
    {
        std::lock_guard<std::mutex> lk(q_->m);
        q_->map_error = std::current_exception();
        q_->to_map.clear();
    }
    {
        std::lock_guard<std::mutex> lk(q_->m);
        q_->map_done = true;
    }
    q_->cv.notify_all();
}

void LivePipeline::run(const std::atomic<bool>& stop,
                       const std::function<void(const LiveStats&, double)>& status)
{
    std::atomic<bool> capture_stop{false};
    // One core for the network, the other for mapping (OpenCV would take both and starve the
    // mapper, which then falls behind the camera).
    if (segmenter_ && o_.segmentation_threads > 0) cv::setNumThreads(o_.segmentation_threads);
    std::thread seg, map([this] { mappingLoop(); });
    if (segmenter_) seg = std::thread([this] { segmentationLoop(); });
    std::thread capture([&] { captureLoop(capture_stop); });
    const auto t0 = std::chrono::steady_clock::now();
    auto next = t0 + std::chrono::seconds(1);
    for (;;)
    {
        if (stop && !capture_stop)
        {
            capture_stop = true;
            // What is queued may still get its pose, for one pose wait at most.
            drain_deadline_ns_ = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                     (std::chrono::steady_clock::now() +
                                      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(std::clamp(o_.pose_wait, 0.0, 1e6))))
                                         .time_since_epoch())
                                     .count();
        }
        {
            std::lock_guard<std::mutex> lk(q_->m);
            // Done once the mapper is: an empty queue alone ended the poses while the last frame
            // still waited for its pose (--max-frames: that frame was always skipped). After a
            // mapping error nothing maps what capture queued before it stopped.
            if (q_->map_error) capture_stop = true;
            if (q_->map_done && q_->capture_done && (!segmenter_ || q_->seg_done)) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (std::chrono::steady_clock::now() >= next)
        {
            next += std::chrono::seconds(1);
            if (status) status(stats_, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
    }
    capture.join();
    if (seg.joinable()) seg.join();
    poses_.stop();
    map.join();
    maps_.finish();
    if (q_->recorder)
    {
        try
        {
            q_->recorder->close();
        }
        catch (...)
        {
            if (!q_->map_error) throw;  // else the same error, or one after the first
        }
        stats_.recorded_frames = q_->recorder->framesWritten();
        stats_.recorded_files = q_->recorder->filesOpened();
        stats_.recorded_files_deleted = q_->recorder->filesDeleted();
        stats_.recorded_bytes = q_->recorder->bytesKept();
    }
    if (q_->map_error) std::rethrow_exception(q_->map_error);
}

}  // namespace pndt::live
