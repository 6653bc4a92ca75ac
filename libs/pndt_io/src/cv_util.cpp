#include "cv_util.h"

#include "text_util.h"

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <pndt/io/images.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <vector>

namespace pndt::io
{
namespace
{
uint32_t be16(const uint8_t* p) { return uint32_t(p[0]) << 8 | p[1]; }
uint32_t be32(const uint8_t* p) { return be16(p) << 16 | be16(p + 2); }
}  // namespace

std::array<int64_t, 2> imageHeaderSize(const uint8_t* b, size_t n)
{
    static const uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (n >= 24 && std::equal(kPng, kPng + 8, b) && std::equal(b + 12, b + 16, "IHDR"))
        return {be32(b + 16), be32(b + 20)};
    if (n >= 4 && b[0] == 0xFF && b[1] == 0xD8)  // JPEG: walk the marker segments to a SOFn
    {
        size_t p = 2;
        while (p + 4 <= n && b[p] == 0xFF)
        {
            const uint8_t marker = b[p + 1];
            if (marker == 0xFF) { ++p; continue; }  // fill byte
            const size_t len = be16(b + p + 2);
            const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
            if (sof) return p + 9 <= n ? std::array<int64_t, 2>{be16(b + p + 7), be16(b + p + 5)}
                                       : std::array<int64_t, 2>{-1, -1};
            if (len < 2) break;
            p += 2 + len;
        }
        return {-1, -1};
    }
    // PNM "P5 <w> <h> ..." with # comments; PFM "PF <w> <h> <scale>" (32-bit float)
    if (n >= 3 && b[0] == 'P' && ((b[1] >= '1' && b[1] <= '6') || b[1] == 'F' || b[1] == 'f'))
    {
        int64_t v[2] = {-1, -1};
        size_t p = 2;
        for (int k = 0; k < 2; ++k)
        {
            while (p < n && (std::isspace(b[p]) || b[p] == '#'))
                if (b[p] == '#')
                    while (p < n && b[p] != '\n') ++p;
                else
                    ++p;
            if (p >= n || !std::isdigit(b[p])) return {-1, -1};
            v[k] = 0;
            while (p < n && std::isdigit(b[p]) && v[k] < (int64_t(1) << 40)) v[k] = v[k] * 10 + (b[p++] - '0');
        }
        return {v[0], v[1]};
    }
    return {-1, -1};
}

bool imageFormatKnown(const uint8_t* b, size_t n)
{
    static const uint8_t kPng[4] = {0x89, 'P', 'N', 'G'};
    if (n >= 4 && std::equal(kPng, kPng + 4, b)) return true;
    if (n >= 2 && b[0] == 0xFF && b[1] == 0xD8) return true;
    return n >= 2 && b[0] == 'P' && ((b[1] >= '1' && b[1] <= '6') || b[1] == 'F' || b[1] == 'f');
}

std::string imageSizeProblem(int64_t w, int64_t h)
{
    if (w < 0 || h < 0) return {};
    if (w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxImagePixels)
        return fmt::format("the image header claims {} x {} pixels, more than a reader accepts ({} per side, {} in "
                           "all); refused before decoding",
                           w, h, kMaxImageSide, kMaxImagePixels);
    return {};
}

std::vector<uint8_t> readCheckedImageBytes(const std::string& path)
{
    detail::requireRegularFile(path);
    // The whole file is read once and decoded from memory, after its header was checked: only
    // formats whose header size is checked here reach a decoder (JPEG 2000, TIFF, EXR, WebP...
    // decoders size allocations from fields this reader does not check).
    std::vector<uint8_t> bytes;
    {
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (ec) detail::failFile(path, fmt::format("cannot read: {}", ec.message()));
        if (size > kMaxImageFileBytes)
            detail::failFile(path, fmt::format("{} bytes, more than an image file may have ({})", size, kMaxImageFileBytes));
        bytes.resize(size_t(size));
        std::ifstream f(path, std::ios::binary);
        f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
        if (!f && !bytes.empty()) detail::failFile(path, "cannot read the file");
    }
    const auto wh = imageHeaderSize(bytes.data(), bytes.size());
    if (wh[0] < 0)
    {
        if (imageFormatKnown(bytes.data(), bytes.size()))
            detail::failFile(path, "cannot decode image: its header is truncated or corrupt");
        detail::failFile(path, "cannot decode image: not a PNG, JPEG, PNM or PFM image (the only formats the image readers decode)");
    }
    if (const std::string problem = imageSizeProblem(wh[0], wh[1]); !problem.empty()) detail::failFile(path, problem);
    // libjpeg only warns at a cut JPEG and OpenCV returns the rows it had, the rest smeared:
    // a JPEG must hold its end-of-image marker (FF D9; some writers pad after it).
    if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF)
    {
        const size_t tail = std::min<size_t>(bytes.size() - 2, 1024);
        bool end_marker = false;
        for (size_t i = bytes.size() - 2; !end_marker && i + tail >= bytes.size() - 2 && i >= 2; --i)
            end_marker = bytes[i] == 0xFF && bytes[i + 1] == 0xD9;
        if (!end_marker)
            detail::failFile(path, "cannot decode image: the JPEG has no end-of-image marker (a cut or truncated file)");
    }
    return bytes;
}
}  // namespace pndt::io

namespace pndt::io::detail
{
cv::Mat readImageUnchanged(const std::string& path)
{
    const std::vector<uint8_t> bytes = readCheckedImageBytes(path);
    cv::Mat m;
    try
    {
        m = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
    }
    catch (const cv::Exception& e)
    {
        failFile(path, fmt::format("cannot decode image: {}", e.what()));
    }
    if (m.empty()) failFile(path, "cannot decode image (corrupt or truncated file)");
    return m;
}

std::string describeMat(const cv::Mat& m)
{
    const char* depth = "unknown-depth";
    switch (m.depth())
    {
        case CV_8U: depth = "8-bit unsigned"; break;
        case CV_8S: depth = "8-bit signed"; break;
        case CV_16U: depth = "16-bit unsigned"; break;
        case CV_16S: depth = "16-bit signed"; break;
        case CV_32S: depth = "32-bit signed"; break;
        case CV_32F: depth = "32-bit float"; break;
        case CV_64F: depth = "64-bit float"; break;
        default: break;
    }
    return fmt::format("{}, {} channel{}", depth, m.channels(), m.channels() == 1 ? "" : "s");
}

}  // namespace pndt::io::detail
