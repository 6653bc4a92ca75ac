// Conversions between MRPT observations and the core's PanopticFrame.
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose3D.h>
#include <pndt/frame.h>

#include <string>

namespace pndt
{
/// "<sensorLabel> @ <timestamp seconds>", used to name observations in errors.
std::string describeObservation(const mrpt::obs::CObservation& obs);

/// Depth (metres along the optical axis) and intrinsics of a range scan. Range
/// images holding Euclidean range (range_is_depth = false) are converted.
/// Throws InputError if the scan has no range image or invalid intrinsics.
void depthFrameFrom(const mrpt::obs::CObservation3DRangeScan& obs, PanopticFrame& out);

/// A view of the scan's uint16 range image as it is stored (rangeUnits metres per
/// unit; z or, with range_is_depth = false, ray length): nothing is copied. The
/// scan (and `source`, which receives describeObservation()) must outlive the view's
/// use. Throws InputError like depthFrameFrom.
FrameView frameViewOf(const mrpt::obs::CObservation3DRangeScan& obs, std::string& source);

/// Decodes the two float32 "id + score" images of design §5 into the frame's
/// label images. Throws InputError naming the observation when an image is not
/// single-channel float, differs in size from the depth, or holds negative or
/// non-finite values; the frame then holds no labels.
void attachPanopticLabels(const mrpt::obs::CObservationImage& semantic, const mrpt::obs::CObservationImage& instance,
                          PanopticFrame& frame);

/// The frame's depth as a range scan (millimetre units, range_is_depth) with
/// the frame's intrinsics; depth beyond 65.535 m or invalid becomes 0. Returns how many
/// positive depths could not be stored that way (>= 65.535 m, or < 0.5 mm, rounding to 0):
/// many of them mean a wrong depth scale upstream.
size_t rangeScanFrom(const PanopticFrame& frame, mrpt::obs::CObservation3DRangeScan& out);

/// The frame's labels as the two design §5 images: `<label>_PANOPTIC_SEMANTIC`
/// (class + S^L) and `<label>_PANOPTIC_INSTANCE` (instance + S^P).
void labelImagesFrom(const PanopticFrame& frame, const std::string& rgbd_label, mrpt::Clock::time_point stamp,
                     mrpt::obs::CObservationImage& semantic, mrpt::obs::CObservationImage& instance);

/// Encodes ids + scores as one float image (score clamped to [0, 0.999], and below the next
/// id: the id stays exact, the score's precision falls with the id: 1/256 at 65536). Ids of
/// 2^24 or more do not fit: InputError naming the first such pixel (so does labelImagesFrom).
void encodeIdScoreImage(const Image<uint32_t>& ids, const Image<float>& scores, mrpt::img::CImage& out);

/// Optical camera pose in the world: robot pose, then the sensor's pose on the
/// robot, then MRPT's sensor axes (x forward, y left, z up) to optical axes.
Pose cameraPoseInWorld(const mrpt::poses::CPose3D& robotPose, const mrpt::poses::CPose3D& sensorPose);
/// Inverse of the axis change: the MRPT sensor pose of an optical camera pose.
mrpt::poses::CPose3D mrptSensorPoseOf(const Pose& T_world_cam);

/// Eigen <-> MRPT pose conversion.
Pose toEigen(const mrpt::poses::CPose3D& p);
mrpt::poses::CPose3D toMrpt(const Pose& T);

}  // namespace pndt
