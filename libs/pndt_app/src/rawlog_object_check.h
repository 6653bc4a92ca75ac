// Issue #23: MRPT's deserialisers allocate whatever a rawlog claims (a string's u32 length,
// a range image's rows x cols, a point count) before reading the bytes, and MRPT 2.5's
// aligned allocator writes through the null pointer a failed allocation returns. So every
// object of a rawlog is first read here: its serialised layout (as MRPT 2.5.8 reads it,
// every version) is walked with every size checked against the readers' limits, its bytes
// are collected as they arrive (never allocated at a claimed size), and only then are the
// checked bytes handed to MRPT through a memory stream.
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <string>

namespace pndt::app::detail
{
/// Longest string accepted inside a rawlog object (labels, camera names, file names).
inline constexpr uint32_t kMaxRawlogString = 4096;
/// Most bytes one rawlog object may have (a 2^26-pixel depth image with its points is less).
inline constexpr uint64_t kMaxRawlogObjectBytes = uint64_t(1) << 30;

/// What readCheckedRawlogObject() found.
enum class RawlogObjectRead
{
    End,        ///< a clean end of the stream (no byte at the object's start)
    Checked,    ///< `bytes` holds the whole object, its layout checked
    Unchecked,  ///< `bytes` holds the whole object; a part of it this reader has no layout
                ///< for was read by MRPT's own reader, unchecked
};

/// Reads one top-level object (MRPT archive object header, body, end flag) from `in` into
/// `bytes`, checking its layout on the way. Throws std::runtime_error naming the class and
/// the field when a size is implausible, a version is not one MRPT 2.5.8 reads, or a colour
/// image's JPEG bytes would not decode. `in` must throw on a short read inside the object.
///
/// Classes checked (all versions MRPT 2.5.8 reads): CObservation3DRangeScan,
/// CObservationImage, CObservationRobotPose, CObservationOdometry, CSensoryFrame,
/// CActionCollection, CActionRobotMovement2D, and inside them CImage, TCamera, CPose3D,
/// CPose2D, CPose3DPDFGaussian, CPosePDFGaussian, CMatrixF, CMatrixD. Another class (a
/// laser scan, an IMU reading, ...) or a scan whose points / range image live in a file of
/// their own is refused when `strict` (the fuzz target: MRPT's reader of it could allocate
/// what the file claims). Otherwise MRPT's reader reads that part from `in` (its bytes are
/// collected as it goes), the walk goes on after it, `Unchecked` is returned and `unchecked`
/// names the first such part: a robot's rawlog with other sensors reads, and the classes
/// listed stay checked around them (a camera scan in a sensory frame after a laser scan).
RawlogObjectRead readCheckedRawlogObject(mrpt::io::CStream& in, std::string& bytes, bool strict,
                                         std::string& unchecked);

}  // namespace pndt::app::detail
