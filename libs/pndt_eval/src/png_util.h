// Private: PNG encoding/decoding through OpenCV with errors that name the file.
#pragma once

#include <opencv2/core.hpp>

#include <string>

namespace pndt::eval::detail
{
/// Encodes `img` as PNG and writes it atomically. Throws io::WriteError naming `path`.
void writePng(const std::string& path, const cv::Mat& img);
/// io::readCheckedImageBytes, then cv::imdecode(IMREAD_UNCHANGED); throws InputError naming `path`.
cv::Mat readImage(const std::string& path);
}  // namespace pndt::eval::detail
