#include "png_util.h"

#include <pndt/io/atomic_file.h>
#include <pndt/io/images.h>
#include <pndt/types.h>

#include <opencv2/imgcodecs.hpp>

#include <vector>

namespace pndt::eval::detail
{
void writePng(const std::string& path, const cv::Mat& img)
{
    std::vector<uchar> buf;
    bool ok = false;
    try
    {
        ok = cv::imencode(".png", img, buf);
    }
    catch (const cv::Exception& e)
    {
        throw io::WriteError("cannot write '" + path + "': PNG encoding failed: " + e.what());
    }
    if (!ok) throw io::WriteError("cannot write '" + path + "': PNG encoding failed");
    io::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(buf.data()), buf.size()));
}

cv::Mat readImage(const std::string& path)
{
    const std::vector<uint8_t> bytes = io::readCheckedImageBytes(path);  // format and size checked first
    cv::Mat m;
    try
    {
        m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception& e)
    {
        throw InputError("cannot decode image '" + path + "': " + e.what());
    }
    if (m.empty()) throw InputError("cannot decode image '" + path + "' (corrupt or truncated file)");
    return m;
}
}  // namespace pndt::eval::detail
