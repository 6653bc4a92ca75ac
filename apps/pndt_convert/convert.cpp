#include "convert.h"
#include "front_end.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <pndt/app/world_up.h>
#include <pndt/io/intrinsics.h>
#include <pndt/io/npz.h>
#include <pndt/io/pose_interpolator.h>
#include <pndt/io/sequence.h>
#include <pndt/mrpt/observation_frame.h>
#include <mrpt/img/CImage.h>
#include <pndt/mrpt/rawlog_frames.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;

namespace pndt::convert
{
namespace
{
constexpr size_t kMaxSkipExamples = 10;

std::string toLower(std::string s)
{
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool isDir(const fs::path& p)
{
    std::error_code ec;
    return fs::is_directory(p, ec);
}
bool isFile(const fs::path& p)
{
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

bool oneOf(const std::string& v, std::initializer_list<const char*> allowed)
{
    for (const char* a : allowed)
        if (v == a) return true;
    return false;
}

/// Throws InputError "<what> must be one of a, b, c (got 'v')".
void requireOneOf(const std::string& what, const std::string& v, std::initializer_list<const char*> allowed)
{
    if (oneOf(v, allowed)) return;
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw InputError(fmt::format("{} must be one of {} (got '{}')", what, list, v));
}

std::string detectFormat(const ConvertOptions& o)
{
    const fs::path dir(o.input);
    if (!o.sequence.empty() || isDir(dir / "depth_intrinsics")) return "nicr";
    if (io::isTumFolder(o.input)) return "tum";
    if (isDir(dir / "depth")) return "redwood";
    throw InputError(fmt::format(
        "{}: cannot tell the dataset format: expected depth/ + camera_primesense.json (Redwood), rgb.txt + "
        "depth.txt or associations.txt (TUM) or depth_intrinsics/ (nicr-scene-analysis-datasets); use --format",
        o.input));
}

bool isRtabmap(io::PoseFormat f)
{
    using F = io::PoseFormat;
    return f == F::Rtabmap0 || f == F::Rtabmap1 || f == F::Rtabmap2 || f == F::Rtabmap4 || f == F::Rtabmap10 ||
           f == F::Rtabmap11;
}

bool poseIsFinite(const Pose& T) { return T.matrix().allFinite(); }

/// Poses of an external file, looked up per frame.
class ExternalPoses
{
   public:
    ExternalPoses(const ConvertOptions& o, ConvertReport& report)
    {
        path_ = o.poses_file;
        if (o.pose_format.empty()) throw InputError("--poses needs --pose-format (tum, rtabmap0..11, redwood, nicr, ...)");
        try
        {
            format_ = io::parsePoseFormat(o.pose_format);
        }
        catch (const InputError& e)
        {
            throw InputError(std::string("--pose-format: ") + e.what());
        }
        const std::string frame = toLower(o.pose_frame), match = toLower(o.pose_match);
        requireOneOf("--pose-frame", frame, {"auto", "camera", "robot"});
        requireOneOf("--pose-match", match, {"auto", "time", "index"});
        robot_frame_ = frame == "robot" || (frame == "auto" && isRtabmap(format_));
        by_index_ = match == "index" || (match == "auto" && io::isStampless(format_));
        if (by_index_ && !io::isStampless(format_))
            throw InputError(fmt::format("--pose-match index needs a stampless pose format (rtabmap0, rtabmap2, "
                                         "rtabmap4, kitti, redwood); '{}' has stamps or frame numbers: use time",
                                         io::toString(format_)));
        if (!fs::exists(path_)) throw InputError(path_ + ": pose file not found");

        io::PoseReadOptions ro;
        ro.non_finite_is_error = o.strict_poses;
        // Index mode: make t the pose's index (block number, frame number) in every format.
        ro.frame_rate_hz = by_index_ ? 1.0 : o.frame_rate_hz;
        io::PoseReadReport rr;
        std::vector<io::StampedPose> poses = io::readPoseFile(path_, format_, ro, &rr);
        report.non_finite_poses += rr.skipped_non_finite;
        for (const auto& w : rr.skipped_where)
            if (report.notes.size() < kMaxSkipExamples) report.notes.push_back("non-finite pose ignored: " + w);
        if (poses.empty())
            throw InputError(path_ + ": no usable pose in the file" +
                             (rr.skipped_non_finite ? fmt::format(" ({} non-finite)", rr.skipped_non_finite) : ""));
        if (by_index_)
        {
            for (const auto& p : poses)
            {
                const int64_t k = std::llround(p.t);
                if (!by_index_map_.emplace(k, p.T_world_sensor).second)
                    throw InputError(fmt::format("{}: two poses have index {}", path_, k));
            }
        }
        else
        {
            try
            {
                interp_ = io::PoseInterpolator(std::move(poses));
            }
            catch (const InputError& e)
            {
                throw InputError(fmt::format("{}: {}", path_, e.what()));
            }
        }
        max_gap_ = o.max_pose_gap;
        time_offset_ = o.pose_time_offset;
        index_offset_ = o.pose_index_offset;
        sensor_pose_ = o.sensor_pose;
        description_ = fmt::format("{} ({}, {} of the {}, matched by {})", path_, io::toString(format_),
                                   robot_frame_ ? "robot poses" : "camera poses",
                                   robot_frame_ ? "body frame" : "optical frame", by_index_ ? "index" : "time");
    }

    /// Camera (optical) pose of frame `index` with stamp t, or nullopt + the reason.
    std::optional<Pose> lookup(size_t index, double t, std::string& reason) const
    {
        std::optional<Pose> T;
        if (by_index_)
        {
            const int64_t k = int64_t(index) + index_offset_;
            auto it = by_index_map_.find(k);
            if (it == by_index_map_.end())
            {
                reason = "no pose: no pose with this index in the pose file";
                return std::nullopt;
            }
            T = it->second;
        }
        else
        {
            const double tq = t + time_offset_;
            T = interp_.at(tq, max_gap_);
            if (!T)
            {
                reason = (tq < interp_.startTime() || tq > interp_.endTime())
                             ? "no pose: frame outside the pose file's time range"
                             : "no pose: gap between poses > max-pose-gap";
                return std::nullopt;
            }
        }
        if (robot_frame_) T = cameraPoseInWorld(toMrpt(*T), sensor_pose_);
        return T;
    }
    const std::string& description() const { return description_; }

   private:
    std::string path_, description_;
    io::PoseFormat format_ = io::PoseFormat::Tum;
    bool robot_frame_ = false, by_index_ = false;
    io::PoseInterpolator interp_;
    std::map<int64_t, Pose> by_index_map_;
    double max_gap_ = 0.1, time_offset_ = 0;
    int64_t index_offset_ = 0;
    mrpt::poses::CPose3D sensor_pose_;
};

template <typename T>
void requireDepthSize(const Image<T>& img, const Image<float>& depth, const std::string& path, const char* what)
{
    if (!img.sameSize(depth.width, depth.height))
        throw InputError(fmt::format("{}: {} is {} x {} but the depth image is {} x {} (labels must be registered "
                                     "to the depth image and of its size)",
                                     path, what, img.width, img.height, depth.width, depth.height));
}

/// EMSANet "id + score" prediction images → frame labels.
void attachPredictions(io::RgbdFrame& f, const io::FrameRecord& rec, PanopticFrame& out)
{
    requireDepthSize(f.pred_semantic, out.depth, rec.pred_semantic_path, "the semantic prediction");
    requireDepthSize(f.pred_instance, out.depth, rec.pred_instance_path, "the instance prediction");
    io::IdScoreImages sem = io::decodeIdScore(f.pred_semantic, rec.pred_semantic_path);
    io::IdScoreImages ins = io::decodeIdScore(f.pred_instance, rec.pred_instance_path);
    out.semantic = std::move(sem.ids);
    out.semantic_score = std::move(sem.scores);
    out.instance.resize(ins.ids.width, ins.ids.height);
    std::copy(ins.ids.data.begin(), ins.ids.data.end(), out.instance.data.begin());
    out.panoptic_score = std::move(ins.scores);
}

/// Ground-truth label images → frame labels with score 1 (stored as 0.999).
void attachGroundTruth(io::RgbdFrame& f, const io::FrameRecord& rec, PanopticFrame& out)
{
    requireDepthSize(f.semantic_gt, out.depth, rec.semantic_path, "the semantic label image");
    out.semantic = std::move(f.semantic_gt);
    out.semantic_score.resize(out.depth.width, out.depth.height, 1.f);
    if (!f.instance_gt.empty())
    {
        requireDepthSize(f.instance_gt, out.depth, rec.instance_path, "the instance label image");
        out.instance.resize(out.depth.width, out.depth.height);
        std::copy(f.instance_gt.data.begin(), f.instance_gt.data.end(), out.instance.data.begin());
        out.panoptic_score.resize(out.depth.width, out.depth.height, 1.f);
    }
}

/// Sets MRPT's process-wide colour-image serialisation mode for its lifetime.
class JpegSerialisation
{
   public:
    explicit JpegSerialisation(int quality)
        : old_disable_(mrpt::img::CImage::DISABLE_JPEG_COMPRESSION()),
          old_quality_(mrpt::img::CImage::SERIALIZATION_JPEG_QUALITY())
    {
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(quality <= 0);
        if (quality > 0) mrpt::img::CImage::SERIALIZATION_JPEG_QUALITY(quality);
    }
    ~JpegSerialisation()
    {
        mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(old_disable_);
        mrpt::img::CImage::SERIALIZATION_JPEG_QUALITY(old_quality_);
    }

   private:
    bool old_disable_;
    int old_quality_;
};

bool sameCamera(const CameraIntrinsics& a, const CameraIntrinsics& b)
{
    auto close = [](double x, double y) { return std::abs(x - y) <= 1e-6 * std::max(1.0, std::abs(x)); };
    return a.width == b.width && a.height == b.height && close(a.fx, b.fx) && close(a.fy, b.fy) &&
           close(a.cx, b.cx) && close(a.cy, b.cy);
}
}  // namespace

size_t ConvertReport::skippedTotal() const
{
    size_t n = 0;
    for (const auto& [k, v] : skipped) n += v;
    return n;
}

Eigen::Vector3d parseUpDirection(const std::string& text, const std::string& option)
{
    std::istringstream in(text);
    Eigen::Vector3d v;
    std::string rest;
    if (!(in >> v.x() >> v.y() >> v.z()) || (in >> rest) || !v.allFinite() || v.norm() < 1e-9)
        throw InputError(fmt::format("{} must be three numbers \"x y z\", not all zero (got '{}')", option, text));
    return v.normalized();
}

mrpt::poses::CPose3D parseSensorPose(const std::string& text)
{
    std::istringstream in(text);
    in.imbue(std::locale::classic());
    double v[6];
    for (double& x : v)
        if (!(in >> x) || !std::isfinite(x))
            throw InputError(fmt::format("--sensor-pose: expected 6 finite numbers 'x y z yaw pitch roll' (metres, "
                                         "degrees), got '{}'",
                                         text));
    std::string rest;
    if (in >> rest) throw InputError(fmt::format("--sensor-pose: unexpected '{}' after 6 numbers in '{}'", rest, text));
    constexpr double d2r = M_PI / 180.0;
    return mrpt::poses::CPose3D(v[0], v[1], v[2], v[3] * d2r, v[4] * d2r, v[5] * d2r);
}

ConvertReport convertSequence(const ConvertOptions& o, const ProgressFn& progress)
{
    const auto t0 = std::chrono::steady_clock::now();
    ConvertReport report;

    // ---- validate everything that needs no file first
    if (o.input.empty()) throw InputError("no input folder given");
    if (o.output.empty()) throw InputError("no output rawlog given (-o)");
    const std::string format = toLower(o.format), labels_opt = toLower(o.labels);
    requireOneOf("--format", format, {"auto", "redwood", "tum", "nicr"});
    requireOneOf("--labels", labels_opt, {"auto", "predictions", "gt", "model", "none"});
    if (o.stride == 0) throw InputError("--stride must be at least 1");
    if (!(o.frame_rate_hz > 0) || !std::isfinite(o.frame_rate_hz))
        throw InputError(fmt::format("--frame-rate must be > 0 (got {})", o.frame_rate_hz));
    if (!(o.max_pose_gap >= 0) || !std::isfinite(o.max_pose_gap))
        throw InputError(fmt::format("--max-pose-gap must be >= 0 seconds (got {})", o.max_pose_gap));
    if (!std::isfinite(o.pose_time_offset)) throw InputError("--pose-time-offset must be finite");
    if (!std::isfinite(o.stamp_offset)) throw InputError("--stamp-offset must be finite");
    if (o.depth_units_per_metre && !(*o.depth_units_per_metre > 0 && std::isfinite(*o.depth_units_per_metre)))
        throw InputError(fmt::format("--depth-scale must be > 0 (got {})", *o.depth_units_per_metre));
    if (o.gz_level < 0 || o.gz_level > 9) throw InputError("--gz-level must be 0..9");
    if (o.color_jpeg_quality < 0 || o.color_jpeg_quality > 100)
        throw InputError("--jpeg-quality must be 0..100 (0 = raw colour)");
    if (o.rgbd_label.empty() || o.pose_label.empty()) throw InputError("sensor labels must not be empty");
    if (!o.poses_file.empty() && o.pose_format.empty())
        throw InputError("--poses needs --pose-format (tum, rtabmap0..11, redwood, nicr, ...)");
    if (!o.pose_format.empty())
    {
        try
        {
            (void)io::parsePoseFormat(o.pose_format);
        }
        catch (const InputError& e)
        {
            throw InputError(std::string("--pose-format: ") + e.what());
        }
        if (o.poses_file.empty()) throw InputError("--pose-format given without --poses FILE");
    }
    // These only tell how to read --poses FILE: without it they would be taken and ignored
    // (robot poses of a sequence's own pose file then mapped as camera poses, exit 0).
    if (o.poses_file.empty())
        for (const auto& [given, option] : {std::pair{toLower(o.pose_frame) != "auto", "--pose-frame"},
                                            std::pair{toLower(o.pose_match) != "auto", "--pose-match"},
                                            std::pair{o.pose_time_offset != 0.0, "--pose-time-offset"},
                                            std::pair{o.pose_index_offset != 0, "--pose-index-offset"}})
            if (given)
                throw InputError(fmt::format("{} given without --poses FILE: it tells how to read a pose file, and "
                                             "a sequence's own poses are taken as they are (camera poses, by stamp)",
                                             option));
    if (!isDir(o.input)) throw InputError(o.input + ": input folder not found");
    if (isDir(o.output)) throw InputError(o.output + ": output path is a folder");

    // ---- open the sequence (indexes files, reads intrinsics and the sequence's own poses)
    report.kind = format == "auto" ? detectFormat(o) : format;
    const bool external = !o.poses_file.empty();
    std::optional<CameraIntrinsics> K_override;
    if (!o.intrinsics_file.empty())
    {
        if (report.kind == "nicr") throw InputError("--intrinsics is for Redwood and TUM folders (nicr has its own)");
        if (!isFile(o.intrinsics_file)) throw InputError(o.intrinsics_file + ": intrinsics file not found");
        K_override = io::readOpen3dIntrinsicsJson(o.intrinsics_file);
    }
    std::string labels = labels_opt;
    if (labels == "auto") labels = !o.model.empty() ? "model" : o.predictions_dir.empty() ? "none" : "predictions";
    if (labels == "model" && o.model.empty()) throw InputError("--labels model needs --model FILE");
    if (labels != "model" && !o.model.empty())
        throw InputError(fmt::format("--model labels every frame; it cannot be combined with --labels {}", labels));
    if (!o.up_world.empty() && o.model.empty() && !o.level)
        throw InputError("--up is for the segmentation front-end (--model) and --level");
    std::optional<Pose> level;  // source world -> levelled world, set at the first pose without --up
    if (o.level && !o.up_world.empty())
    {
        const Eigen::Vector3d up = parseUpDirection(o.up_world);
        level = app::levellingRotation(up);
        report.levelled_up = up;
    }
    if (report.kind != "nicr" && labels != "none" && labels != "model")
        throw InputError(fmt::format("--labels {}: only nicr-scene-analysis-datasets folders carry labels", labels));
    if (labels == "predictions" && o.predictions_dir.empty())
        throw InputError("--labels predictions needs --predictions DIR (EMSANet's mapping output folder)");

    io::RgbdSequence seq;
    std::string sequence_pose_file;
    if (report.kind == "redwood")
    {
        io::RedwoodOptions ro;
        ro.frame_rate_hz = o.frame_rate_hz;
        if (o.depth_units_per_metre) ro.depth_units_per_metre = *o.depth_units_per_metre;
        ro.intrinsics = K_override;
        ro.non_finite_pose_is_error = o.strict_poses;
        if (external) ro.trajectory_file.clear();  // the folder's own .log is not used
        seq = io::openRedwoodSequence(o.input, ro);
        if (!external) sequence_pose_file = (fs::path(o.input) / ro.trajectory_file).string();
    }
    else if (report.kind == "tum")
    {
        io::TumOptions to;
        to.frame_rate_hz = o.frame_rate_hz;
        if (o.depth_units_per_metre) to.depth_units_per_metre = *o.depth_units_per_metre;
        to.intrinsics = K_override;
        to.max_pose_gap = o.max_pose_gap;
        if (external) to.groundtruth_file.clear();
        seq = io::openTumSequence(o.input, to);
        if (!external)
        {
            sequence_pose_file = (fs::path(o.input) / to.groundtruth_file).string();
            if (o.strict_poses && seq.non_finite_poses > 0)
            {
                io::PoseReadOptions strict;
                strict.non_finite_is_error = true;
                (void)io::readTumPoses(sequence_pose_file, strict);  // throws naming file and line
            }
        }
    }
    else
    {
        std::string sequence = o.sequence;
        if (sequence.empty())
        {
            const auto all = io::listNicrSequences(o.input);
            if (all.size() != 1)
            {
                std::string list;
                for (size_t i = 0; i < all.size() && i < 10; ++i) list += (i ? ", " : "") + all[i];
                if (all.size() > 10) list += ", ...";
                throw InputError(fmt::format("{}: {} sequences, choose one with --sequence ({})", o.input, all.size(),
                                             list.empty() ? "none found" : list));
            }
            sequence = all.front();
        }
        io::NicrOptions no;
        no.frame_rate_hz = o.frame_rate_hz;
        no.depth_units_per_metre = o.depth_units_per_metre;
        no.semantic_dir = labels == "gt" ? o.semantic_dir : "-";
        no.instance_dir = labels == "gt" ? o.instance_dir : "-";
        no.predictions_dir = labels == "predictions" ? o.predictions_dir : "";
        seq = io::openNicrSequence(o.input, sequence, no);
        if (!external)
        {
            sequence_pose_file = (fs::path(o.input) / "extrinsics" / sequence).string();
            if (o.strict_poses && seq.non_finite_poses > 0)
            {
                io::PoseReadOptions strict;
                strict.non_finite_is_error = true;
                (void)io::readNicrPoses(sequence_pose_file, strict);  // throws naming the file
            }
        }
    }
    report.source = seq.source;
    report.frames_in_source = seq.size();

    // ---- poses
    std::optional<ExternalPoses> ext;
    if (external)
    {
        ext.emplace(o, report);
        report.pose_source = ext->description();
    }
    else
    {
        report.pose_source = "the sequence's own (" + sequence_pose_file + ")";
        report.non_finite_poses += seq.non_finite_poses;
    }

    // ---- frames
    std::vector<size_t> selected;
    for (size_t i = o.start; i < seq.size() && (o.max_frames == 0 || selected.size() < o.max_frames); i += o.stride)
        selected.push_back(i);
    report.frames_selected = selected.size();
    if (selected.empty())
        throw InputError(fmt::format("{}: no frame selected ({} frames, --start {}, --stride {})", o.input,
                                     seq.size(), o.start, o.stride));

    {
        const fs::path parent = fs::path(o.output).parent_path();
        std::error_code ec;
        if (!parent.empty()) fs::create_directories(parent, ec);
        if (ec) throw std::runtime_error(fmt::format("{}: cannot create folder: {}", parent.string(), ec.message()));
    }
    std::optional<FrontEnd> front_end;
    // In a levelled world the front-end's up is +z.
    if (labels == "model") front_end.emplace(o.model, level ? std::string("0 0 1") : o.up_world, report);
    app::CameraUpTally camera_up;
    // The up of the poses' own frame: the robot's z with a sensor pose (the mount), else the
    // camera's -y (the identity mount gives the same).
    const Eigen::Vector3d up_in_camera = app::robotUpInCamera(o.sensor_pose);

    const JpegSerialisation jpeg(o.color_jpeg_quality);
    RawlogFrameWriter writer(o.output, o.rgbd_label, o.gz_level);
    writer.setSensorPose(o.sensor_pose);

    io::FrameLoadOptions lo;
    lo.color = o.color || front_end;  // the front-end needs colour even when it is not embedded
    lo.labels = labels == "gt";
    lo.predictions = labels == "predictions";

    auto skip = [&](const std::string& reason, const io::FrameRecord& rec, const std::string& detail) {
        ++report.skipped[reason];
        if (report.skip_examples.size() < kMaxSkipExamples)
            report.skip_examples.push_back(
                fmt::format("frame {} (t={:.6f}): {}{}", rec.id, rec.t, reason, detail.empty() ? "" : ": " + detail));
    };
    size_t color_unregistered = 0;
    size_t depth_pixels = 0;  // positive depths of the frames written

    for (size_t n = 0; n < selected.size(); ++n)
    {
        if (progress) progress(n, selected.size());
        const size_t idx = selected[n];
        const io::FrameRecord& rec = seq.frames[idx];

        // Pose first: a frame without one is skipped before its images are decoded.
        std::optional<Pose> T;
        std::string reason;
        if (ext)
            T = ext->lookup(idx, rec.t, reason);
        else
        {
            T = rec.T_world_cam;
            if (!T) reason = "no pose: none in the sequence for this frame";
        }
        if (T && !poseIsFinite(*T))
        {
            T.reset();
            reason = "no pose: non-finite";
        }
        if (!T)
        {
            skip(reason, rec, "");
            continue;
        }
        if (o.level && !level)
        {
            // Without --up: the world axis nearest the first frame's up (a camera's own tilt
            // is no part of the world's turn; a z-up world is left as it is).
            report.level_observed = app::worldUp(*T, up_in_camera);
            report.levelled_up = app::nearestAxis(*report.level_observed);
            level = app::levellingRotation(*report.levelled_up);
        }
        if (level) T = *level * *T;
        camera_up.add(*T, up_in_camera);

        PanopticFrame pf;
        io::RgbdFrame f;
        bool labels_missing = false, instances_missing = false;
        try
        {
            f = seq.load(idx, lo);
            pf.K = f.K;
            pf.source = rec.depth_path;
            pf.depth = std::move(f.depth);
            if (labels == "predictions")
            {
                if (!f.pred_semantic.empty() && !f.pred_instance.empty())
                    attachPredictions(f, rec, pf);
                else
                    labels_missing = true;
            }
            else if (labels == "gt")
            {
                if (!f.semantic_gt.empty())
                {
                    attachGroundTruth(f, rec, pf);
                    instances_missing = f.instance_gt.empty() && rec.instance_path.empty();
                }
                else
                    labels_missing = true;
            }
        }
        catch (const InputError& e)
        {
            if (!o.skip_bad_frames) throw;
            skip("unreadable frame", rec, e.what());
            continue;
        }

        const Image<std::array<uint8_t, 3>>* registered = nullptr;
        if (!f.color.empty())
        {
            if (f.color.sameSize(pf.depth.width, pf.depth.height) && sameCamera(f.K, f.K_color))
                registered = &f.color;
            else
                ++color_unregistered;
        }
        if (front_end) front_end->label(pf, registered, *T);
        const Image<std::array<uint8_t, 3>>* rgb = o.color ? registered : nullptr;
        writer.write(pf, rec.t + o.stamp_offset, T, rgb, o.pose_label);
        for (const float d : pf.depth.data) depth_pixels += d > 0 && std::isfinite(d);
        ++report.frames_written;
        if (pf.hasLabels()) ++report.frames_with_labels;
        if (labels_missing) ++report.frames_labels_missing;
        if (instances_missing) ++report.frames_instances_missing;
        if (rgb) ++report.frames_with_color;
    }
    if (progress) progress(selected.size(), selected.size());
    if (color_unregistered)
        report.notes.push_back(fmt::format("colour not embedded in {} frames: not registered to the depth image "
                                           "(other size or intrinsics)",
                                           color_unregistered));
    if (report.frames_written == 0)
    {
        std::string reasons;
        for (const auto& [reason, n] : report.skipped) reasons += fmt::format("{}{} x {}", reasons.empty() ? "" : "; ", n, reason);
        throw InputError(fmt::format("{}: no frame written, all {} selected frames were skipped ({}); nothing written "
                                     "to {}{}",
                                     o.input, selected.size(), reasons, o.output,
                                     external ? "" : " (poses from a file: --poses FILE --pose-format FORMAT)"));
    }
    // A rawlog stores millimetres in 16 bits: depths that do not fit are lost. Most of them lost
    // is a wrong depth scale (millimetres read as metres), not a scene.
    if (const size_t lost = writer.unstoredDepthPixels(); lost > 0)
    {
        const std::string what = fmt::format(
            "{} of {} depth pixels ({:.1f} %) are outside the 0.5 mm - 65.535 m a rawlog stores and were written as no "
            "depth (a wrong --depth-scale? the depth images were read with {})",
            lost, depth_pixels, 100.0 * double(lost) / double(std::max<size_t>(depth_pixels, 1)),
            o.depth_units_per_metre ? fmt::format("{} units per metre", *o.depth_units_per_metre)
                                    : std::string("the format's default units"));
        if (2 * lost > depth_pixels) throw InputError(fmt::format("{}: {}; nothing written to {}", o.input, what, o.output));
        report.notes.push_back(what);
    }
    if (report.levelled_up)
        report.level_degrees = app::angleDegrees(*report.levelled_up, Eigen::Vector3d::UnitZ());
    else if (const auto note = camera_up.notZUpNote(
                 "--level writes the rawlog in a world turned to z up; with --up when the cameras do not stand upright"))
        report.notes.push_back(*note);
    writer.commit();

    std::error_code ec;
    report.output_bytes = fs::file_size(o.output, ec);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return report;
}

std::string formatReport(const ConvertReport& r, const ConvertOptions& o)
{
    std::string s;
    s += fmt::format("pndt-convert: {} sequence {} -> {}\n", r.kind, r.source, o.output);
    s += fmt::format("  frames in source   : {} (selected {})\n", r.frames_in_source, r.frames_selected);
    s += fmt::format("  frames written     : {}\n", r.frames_written);
    s += fmt::format("  with labels        : {}{}\n", r.frames_with_labels,
                     r.frames_labels_missing ? fmt::format(" ({} frames had no labels: geometry only)",
                                                           r.frames_labels_missing)
                                             : "");
    if (r.frames_instances_missing)
        s += fmt::format("  without instances  : {} frames had semantic but no instance labels (their things have no "
                         "instance ids)\n",
                         r.frames_instances_missing);
    s += fmt::format("  with colour        : {}\n", r.frames_with_color);
    s += fmt::format("  frames skipped     : {}\n", r.skippedTotal());
    for (const auto& [reason, n] : r.skipped) s += fmt::format("    {:>6}  {}\n", n, reason);
    for (const auto& e : r.skip_examples) s += fmt::format("    e.g. {}\n", e);
    s += fmt::format("  poses              : {}\n", r.pose_source);
    if (r.levelled_up && r.level_degrees == 0)
        s += fmt::format("  world levelled     : the first frame's up {} is nearest +z: not turned\n",
                         app::directionText(r.level_observed.value_or(*r.levelled_up), 3));
    else if (r.levelled_up)
        s += fmt::format("  world levelled     : up {}{} turned to +z ({:.1f} degrees)\n",
                         app::directionText(*r.levelled_up, 3),
                         r.level_observed ? " (nearest the first frame's up " +
                                                app::directionText(*r.level_observed, 3) + ")"
                                          : std::string(),
                         r.level_degrees);
    if (r.non_finite_poses) s += fmt::format("  non-finite poses   : {} (ignored)\n", r.non_finite_poses);
    for (const auto& n : r.notes) s += fmt::format("  note: {}\n", n);
    if (r.frames_segmented)
    {
        const double n = double(r.frames_segmented);
        const double per_frame = (r.segment_preprocess_ms + r.segment_network_ms + r.segment_postprocess_ms) / n;
        s += fmt::format("  segmentation       : {}\n", r.segmenter);
        s += fmt::format("    {} frames, {:.1f} ms/frame ({:.1f} frames/s): preprocess {:.1f}, network {:.1f}, "
                         "post-processing {:.1f} ms\n",
                         r.frames_segmented, per_frame, per_frame > 0 ? 1000.0 / per_frame : 0.0,
                         r.segment_preprocess_ms / n, r.segment_network_ms / n, r.segment_postprocess_ms / n);
        for (const auto& [c, k] : r.detections_per_class) s += fmt::format("    detections {:>6}  {}\n", k, c);
        for (const auto& [c, k] : r.instances_per_class)
            s += fmt::format("    instances  {:>6}  {} ({:.2f} per frame)\n", k, c, double(k) / n);
    }
    s += fmt::format("  time               : {:.2f} s ({:.1f} frames/s)\n", r.seconds,
                     r.seconds > 0 ? double(r.frames_written) / r.seconds : 0.0);
    s += fmt::format("  output             : {} ({:.1f} MB)", o.output, double(r.output_bytes) / 1e6);
    return s;
}

std::string reportJson(const ConvertReport& r, const ConvertOptions& o)
{
    nlohmann::json j;
    j["kind"] = r.kind;
    j["source"] = r.source;
    j["output"] = o.output;
    j["frames_in_source"] = r.frames_in_source;
    j["frames_selected"] = r.frames_selected;
    j["frames_written"] = r.frames_written;
    j["frames_with_labels"] = r.frames_with_labels;
    j["frames_labels_missing"] = r.frames_labels_missing;
    j["frames_instances_missing"] = r.frames_instances_missing;
    j["frames_with_color"] = r.frames_with_color;
    j["frames_skipped"] = r.skippedTotal();
    j["skipped"] = nlohmann::json::object();
    for (const auto& [reason, n] : r.skipped) j["skipped"][reason] = n;
    j["skip_examples"] = r.skip_examples;
    j["pose_source"] = r.pose_source;
    j["non_finite_poses"] = r.non_finite_poses;
    if (r.levelled_up)
        j["levelled"] = {{"up", {r.levelled_up->x(), r.levelled_up->y(), r.levelled_up->z()}},
                         {"degrees", r.level_degrees}};
    j["notes"] = r.notes;
    if (r.frames_segmented)
    {
        auto& sj = j["segmentation"];
        sj["segmenter"] = r.segmenter;
        sj["frames"] = r.frames_segmented;
        const double n = double(r.frames_segmented);
        sj["ms_per_frame"] = {{"preprocess", r.segment_preprocess_ms / n},
                              {"network", r.segment_network_ms / n},
                              {"postprocess", r.segment_postprocess_ms / n}};
        sj["detections_per_class"] = r.detections_per_class;
        sj["instances_per_class"] = r.instances_per_class;
    }
    j["seconds"] = r.seconds;
    j["output_bytes"] = r.output_bytes;
    return j.dump(2);
}

}  // namespace pndt::convert
