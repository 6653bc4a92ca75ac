// Internal: OpenCV decoding with errors that name the file.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace pndt::io::detail
{
/// readCheckedImageBytes, then cv::imdecode(IMREAD_UNCHANGED); throws InputError "file not found",
/// "not a PNG, JPEG, PNM or PFM image", "cannot decode image".
cv::Mat readImageUnchanged(const std::string& path);
/// e.g. "16-bit unsigned, 1 channel".
std::string describeMat(const cv::Mat& m);

}  // namespace pndt::io::detail
