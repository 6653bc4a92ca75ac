// Image readers (OpenCV imgcodecs underneath): depth PNG → metres, colour → RGB, label PNGs.
// Every failure (missing file, undecodable file, wrong bit depth or channel count) throws
// pndt::InputError naming the file and what was found.
#pragma once

#include <pndt/types.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pndt::io
{
using RgbImage = Image<std::array<uint8_t, 3>>;

/// Depth units per metre of the common datasets.
inline constexpr double kDepthUnitsMillimetre = 1000.0;  ///< Redwood, ScanNet, Hypersim (nicr)
inline constexpr double kDepthUnitsTum = 5000.0;         ///< TUM RGB-D

/// Allocation limits of every image reader (depth, colour, label, and the rawlog colour-image
/// guard): a file whose header claims more is refused before anything is decoded or allocated
/// (InputError naming the file and the claimed size). 8192 x 8192 pixels = 128 MiB at 16 bit.
inline constexpr int64_t kMaxImageSide = 32768;
inline constexpr int64_t kMaxImagePixels = int64_t(1) << 26;

/// Image files larger than this are refused unread (an uncompressed PNM at the pixel limit
/// with 4 channels of 16 bit is 512 MiB).
inline constexpr uint64_t kMaxImageFileBytes = uint64_t(1) << 30;

/// Width and height claimed by the header of PNG, JPEG (SOF marker), binary/ASCII PNM or PFM
/// bytes; {-1, -1} for other formats or a header too short to tell. The readers decode only
/// these formats: other decoders (JPEG 2000, TIFF, ...) size allocations from unchecked fields.
std::array<int64_t, 2> imageHeaderSize(const uint8_t* bytes, size_t size);
/// Whether the bytes start like PNG, JPEG, PNM or PFM (the formats imageHeaderSize reads).
bool imageFormatKnown(const uint8_t* bytes, size_t size);
/// Empty when `width` x `height` is within the limits above, else why not.
std::string imageSizeProblem(int64_t width, int64_t height);
/// The bytes of an image file for a decoder (cv::imdecode), read once, after its format and
/// header size were checked: throws InputError naming the file when it is not PNG, JPEG, PNM
/// or PFM, its header is truncated, or it claims more than the limits above.
std::vector<uint8_t> readCheckedImageBytes(const std::string& path);

/// 16-bit single-channel PNG (or 16-bit PGM) → metres:
/// metres = raw / units_per_metre; raw 0 → 0 (invalid). Throws on 8-bit, multi-channel or float
/// images and on units_per_metre <= 0.
Image<float> readDepthImage(const std::string& path, double units_per_metre = kDepthUnitsMillimetre);

/// 8-bit 3-channel (BGR on disk order as decoded by OpenCV) or 4-channel (alpha dropped) image
/// (PNG, JPEG, PPM...) → RGB. Grey-level or 16-bit images throw.
RgbImage readColorImage(const std::string& path);

/// Label image → uint16 ids:
///  * 8- or 16-bit single channel: the pixel value (semantic classes, ScanNet instances);
///  * 8-bit 3-channel: the Hypersim/nicr instance encoding, id = (G << 8) | B (R holds the
///    semantic class and is ignored).
Image<uint16_t> readLabelImage(const std::string& path);

}  // namespace pndt::io
