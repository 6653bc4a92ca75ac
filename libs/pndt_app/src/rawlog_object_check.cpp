// The layouts below are those MRPT 2.5.8's serializeFrom() methods read (libs/obs, libs/img,
// libs/poses, libs/math, libs/serialization: CArchive object headers, strings, maps); every
// field that MRPT sizes an allocation from is bounded here before MRPT sees it.
#include "rawlog_object_check.h"

#include <fmt/format.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/io/images.h>

#include <algorithm>
#include <csetjmp>
#include <cstdio>  // before jpeglib.h, which needs FILE
#include <cstring>
#include <initializer_list>
#include <stdexcept>
#include <vector>

#include <jpeglib.h>

namespace pndt::app::detail
{
namespace
{
constexpr uint8_t kEndFlag = 0x88;              ///< MRPT's SERIALIZATION_END_FLAG
constexpr uint64_t kChunk = uint64_t(4) << 20;  ///< bytes are collected as they arrive, 4 MiB at a time
constexpr uint32_t kMaxElements = 4096;         ///< observations in a sensory frame, actions, label names
constexpr uint32_t kMaxParticles = 1000000;     ///< particles of a 2D odometry motion model (default 300)

/// "mrpt::poses::CPose3D" -> "CPose3D" (MRPT registers both spellings and writes the short one).
std::string shortName(const std::string& cls)
{
    if (cls.rfind("mrpt::", 0) == 0) return cls.substr(cls.rfind("::") + 2);
    return cls;
}

/// libjpeg's error handler that returns (MRPT's, the default one, calls exit()).
struct JpegErrors
{
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};
void jpegError(j_common_ptr c)
{
    auto* e = reinterpret_cast<JpegErrors*>(c->err);
    (*c->err->format_message)(c, e->message);
    std::longjmp(e->jump, 1);
}
void jpegWarning(j_common_ptr, int) {}  // MRPT's decoder prints warnings and goes on

struct JpegCheck
{
    std::string problem;  ///< empty: libjpeg decodes the bytes
    bool too_large = false;
};
/// Decodes JPEG bytes with the libjpeg MRPT uses and the calls its CImage::loadFromStreamAsJPEG
/// makes (header, start, every scanline, finish: a structure error after the image data ends
/// there too), at 1/8 scale, after checking the size the header claims against the limits.
JpegCheck checkJpeg(const uint8_t* bytes, size_t n)
{
    jpeg_decompress_struct cinfo{};
    JpegErrors errors{};
    cinfo.err = jpeg_std_error(&errors.mgr);
    errors.mgr.error_exit = jpegError;
    errors.mgr.emit_message = jpegWarning;
    JpegCheck* volatile result = new JpegCheck;  // survives the longjmp
    if (setjmp(errors.jump))
    {
        jpeg_destroy_decompress(&cinfo);
        result->problem = errors.message;
        JpegCheck out = std::move(*result);
        delete result;
        return out;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, const_cast<unsigned char*>(bytes), static_cast<unsigned long>(n));
    jpeg_read_header(&cinfo, TRUE);
    if (std::string problem = io::imageSizeProblem(cinfo.image_width, cinfo.image_height); !problem.empty())
    {
        result->problem = std::move(problem);
        result->too_large = true;
    }
    else
    {
        cinfo.scale_num = 1;
        cinfo.scale_denom = 8;
        jpeg_start_decompress(&cinfo);
        JSAMPARRAY row = (*cinfo.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&cinfo), JPOOL_IMAGE,
                                                     cinfo.output_width * cinfo.output_components, 1);
        while (cinfo.output_scanline < cinfo.output_height) jpeg_read_scanlines(&cinfo, row, 1);
        jpeg_finish_decompress(&cinfo);
    }
    jpeg_destroy_decompress(&cinfo);
    JpegCheck out = std::move(*result);
    delete result;
    return out;
}

/// The stream MRPT's own reader reads an unchecked part from: the part's header bytes (already
/// collected), then the file, every byte collected as it arrives.
class CollectingInput : public mrpt::io::CStream
{
   public:
    CollectingInput(mrpt::io::CStream& in, std::string& buf, size_t part_start)
        : in_(in), buf_(buf), replay_(part_start)
    {
    }
    size_t Read(void* buffer, size_t count) override
    {
        auto* out = static_cast<char*>(buffer);
        const size_t replayed = std::min(count, buf_.size() - replay_);
        std::memcpy(out, buf_.data() + replay_, replayed);
        replay_ += replayed;
        if (replayed == count) return count;
        const size_t want = count - replayed;
        if (buf_.size() + want > kMaxRawlogObjectBytes)
            throw std::runtime_error(
                fmt::format("an object larger than a reader accepts ({} bytes)", kMaxRawlogObjectBytes));
        const size_t at = buf_.size();
        buf_.resize(at + want);
        const size_t got = in_.Read(&buf_[at], want);
        buf_.resize(at + got);
        replay_ = buf_.size();
        std::memcpy(out + replayed, buf_.data() + at, got);
        return replayed + got;
    }
    size_t Write(const void*, size_t) override { throw std::logic_error("read-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error("cannot seek"); }
    uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
    uint64_t getPosition() const override { return in_.getPosition(); }

   private:
    mrpt::io::CStream& in_;
    std::string& buf_;
    size_t replay_;
};

class Walker
{
   public:
    Walker(mrpt::io::CStream& in, std::string& bytes, bool strict) : in_(in), buf_(bytes), strict_(strict) {}

    RawlogObjectRead top(std::string& unchecked)
    {
        buf_.clear();
        buf_.resize(1);
        if (in_.Read(&buf_[0], 1) != 1)
        {
            buf_.clear();
            return RawlogObjectRead::End;  // clean end between objects
        }
        const Header h = header(uint8_t(buf_[0]));
        if (h.name == "nullptr")
            endFlag(h);
        else
        {
            const std::string cls = shortName(h.name);
            static const std::initializer_list<const char*> kTop = {
                "CObservation3DRangeScan", "CObservationImage", "CObservationRobotPose", "CObservationOdometry",
                "CSensoryFrame",           "CActionCollection"};
            if (std::none_of(kTop.begin(), kTop.end(), [&](const char* c) { return cls == c; }))
                readUnchecked(0, fmt::format("a '{}' object", h.name),
                              "it reads CObservation3DRangeScan, CObservationImage, CObservationRobotPose, "
                              "CObservationOdometry, CSensoryFrame and CActionCollection (their sizes are checked "
                              "before MRPT allocates them)");
            else
                body(h, cls);
        }
        if (first_unchecked_.empty()) return RawlogObjectRead::Checked;
        unchecked = first_unchecked_;
        return RawlogObjectRead::Unchecked;
    }

   private:
    struct Header
    {
        std::string name;
        unsigned version = 0;
        bool old = false;  ///< the pre-0.5.5 header: no end flag
    };

    /// A part without a layout here: refused when strict, else noted (the caller reads it).
    void notChecked(const std::string& part, const std::string& why)
    {
        if (strict_) fail(fmt::format("{}, which this reader does not accept: {}", part, why));
        if (!first_unchecked_.empty()) return;
        std::string where;
        for (const auto& c : context_) where += (where.empty() ? "" : " > ") + c;
        first_unchecked_ = where.empty() ? part : where + ": " + part;
    }
    /// An object of a class without a layout here, whose header starts at buf_[start]: MRPT's
    /// reader reads it (header again, body, end flag), its bytes collected; the walk goes on.
    void readUnchecked(size_t start, const std::string& part, const std::string& why)
    {
        notChecked(part, why);
        CollectingInput collect(in_, buf_, start);
        auto archive = mrpt::serialization::archiveFrom(collect);
        (void)archive.ReadObject();
    }

    [[noreturn]] void fail(const std::string& what) const
    {
        std::string where;
        for (const auto& c : context_) where += (where.empty() ? "" : " > ") + c;
        throw std::runtime_error(where.empty() ? what : where + ": " + what);
    }

    /// Appends `n` bytes of the stream (which throws on a short read).
    void take(uint64_t n, const char* what)
    {
        if (n > kMaxRawlogObjectBytes - std::min<uint64_t>(buf_.size(), kMaxRawlogObjectBytes))
            fail(fmt::format("{} of {} bytes makes the object larger than a reader accepts ({} bytes)", what, n,
                             kMaxRawlogObjectBytes));
        while (n > 0)
        {
            const size_t step = size_t(std::min(n, kChunk)), at = buf_.size();
            buf_.resize(at + step);
            if (in_.Read(&buf_[at], step) != step) fail(fmt::format("the file ends inside {}", what));
            n -= step;
        }
    }
    template <class T>
    T get(const char* what = "a field")
    {
        const size_t at = buf_.size();
        take(sizeof(T), what);
        T v;
        std::memcpy(&v, buf_.data() + at, sizeof(T));  // rawlogs are little-endian, as this machine
        return v;
    }
    void skip(uint64_t n) { take(n, "fixed-size fields"); }
    bool flag(const char* what)
    {
        const auto b = get<uint8_t>(what);
        if (b > 1) fail(fmt::format("{} is a bool holding {}", what, unsigned(b)));
        return b == 1;
    }
    void str(const char* what)
    {
        const auto n = get<uint32_t>(what);
        if (n > kMaxRawlogString)
            fail(fmt::format("{} claims a string of {} bytes, more than a reader accepts ({})", what, n,
                             kMaxRawlogString));
        take(n, what);
    }
    /// `first` x `second` pixels within the image readers' limits; `order` names the two.
    void checkSize(const char* what, int64_t first, int64_t second, const char* order)
    {
        if (first < 0 || second < 0 || first > io::kMaxImageSide || second > io::kMaxImageSide ||
            first * second > io::kMaxImagePixels)
            fail(fmt::format("{} of {} x {} pixels ({}), more than a reader accepts ({} per side, {} in all); "
                             "refused before allocating",
                             what, first, second, order, io::kMaxImageSide, io::kMaxImagePixels));
    }
    void checkImage(const char* what, int64_t width, int64_t height)
    {
        checkSize(what, width, height, "width x height");
    }
    void checkRowsCols(const char* what, int64_t rows, int64_t cols) { checkSize(what, rows, cols, "rows x cols"); }

    Header header(uint8_t first)
    {
        Header h;
        h.old = !(first & 0x80);
        if (h.old)
        {
            const size_t at = buf_.size();
            skip(3);
            if (buf_[at] || buf_[at + 1] || buf_[at + 2])
                fail("an object header that is neither MRPT's format nor its pre-0.5.5 one");
        }
        const unsigned length = first & 0x7F;
        if (length > 120) fail(fmt::format("a class name of {} characters (MRPT's limit is 120)", length));
        const size_t at = buf_.size();
        take(length, "a class name");
        h.name = buf_.substr(at, length);
        if (h.old)
        {
            const auto v = get<int32_t>("an object version");
            if (v < 0 || v >= 255) fail(fmt::format("a '{}' object of version {}", h.name, v));
            h.version = unsigned(v);
        }
        else if (h.name != "nullptr")
            h.version = get<uint8_t>("an object version");
        return h;
    }
    void endFlag(const Header& h)
    {
        if (h.old) return;
        const auto f = get<uint8_t>("an end flag");
        if (f != kEndFlag) fail(fmt::format("the end flag of a '{}' object is 0x{:02x}, not 0x88", h.name, f));
    }
    /// A nested object of one of the classes `expected` (short names); returns its class.
    std::string object(const char* what, std::initializer_list<const char*> expected)
    {
        const size_t start = buf_.size();
        const Header h = header(get<uint8_t>(what));
        const std::string cls = shortName(h.name);
        if (std::none_of(expected.begin(), expected.end(), [&](const char* c) { return cls == c; }))
        {
            std::string list;
            for (const char* c : expected) list += (list.empty() ? "" : " or ") + std::string(c);
            readUnchecked(start, fmt::format("{} is a '{}' object", what, h.name), "there it accepts " + list);
            return cls;
        }
        body(h, cls);
        return cls;
    }
    void versions(unsigned v, unsigned lo, unsigned hi)
    {
        if (v < lo || v > hi) fail(fmt::format("version {} is not one MRPT 2.5.8 reads ({}..{})", v, lo, hi));
    }

    void body(const Header& h, const std::string& cls)
    {
        context_.push_back(fmt::format("{} v{}", cls, h.version));
        const unsigned v = h.version;
        if (cls == "CObservation3DRangeScan") scan3D(v);
        else if (cls == "CObservationImage") observationImage(v);
        else if (cls == "CObservationRobotPose") robotPose(v);
        else if (cls == "CObservationOdometry") odometry(v);
        else if (cls == "CSensoryFrame") sensoryFrame(v);
        else if (cls == "CActionCollection") actionCollection(v);
        else if (cls == "CActionRobotMovement2D") robotMovement2D(v);
        else if (cls == "CImage") image(v);
        else if (cls == "TCamera") camera(v);
        else if (cls == "CPose3D") pose3D(v);
        else if (cls == "CPose2D") pose2D(v);
        else if (cls == "CPose3DPDFGaussian") pose3DPdf(v);
        else if (cls == "CPosePDFGaussian") posePdf(v);
        else if (cls == "CMatrixF" || cls == "CMatrixD") matrixBody(v, cls == "CMatrixF" ? 4 : 8);
        else fail("internal: no layout for " + cls);
        context_.pop_back();
        endFlag(h);
    }

    // ---- math and poses
    void matrixBody(unsigned v, uint64_t element_bytes)
    {
        versions(v, 0, 0);
        const auto rows = get<uint32_t>("a matrix's rows"), cols = get<uint32_t>("a matrix's columns");
        last_rows_ = rows;
        last_cols_ = cols;
        if (int64_t(rows) * cols > max_matrix_elements_)
            fail(fmt::format("a matrix of {} x {} elements, more than {} accepts", rows, cols, matrix_what_));
        take(uint64_t(rows) * cols * element_bytes, "a matrix's elements");
    }
    /// A CMatrixF / CMatrixD object of exactly `rows` x `cols` (MRPT checks the shape only after
    /// allocating what the file claims), or any shape up to `max_elements` when rows < 0.
    void matrix(const char* what, bool is_float, int64_t rows, int64_t cols, int64_t max_elements = 0)
    {
        max_matrix_elements_ = rows >= 0 ? rows * cols : max_elements;
        matrix_what_ = what;
        object(what, {is_float ? "CMatrixF" : "CMatrixD"});
        if (rows >= 0 && (last_rows_ != rows || last_cols_ != cols))
            fail(fmt::format("{} is a {} x {} matrix, not {} x {}", what, last_rows_, last_cols_, rows, cols));
    }
    void pose3D(unsigned v)
    {
        versions(v, 0, 3);
        if (v == 0) matrix("a CPose3D's matrix", true, 4, 4);
        else if (v == 1) matrix("a CPose3D's matrix", false, 4, 4);
        else skip(v == 2 ? 7 * 8 : 12 * 8);
    }
    void pose2D(unsigned v)
    {
        versions(v, 0, 1);
        skip(v == 0 ? 3 * 4 : 3 * 8);
    }
    void pose3DPdf(unsigned v)
    {
        versions(v, 1, 1);
        object("a pose's mean", {"CPose3D"});
        skip(21 * 8);
    }
    void posePdf(unsigned v)
    {
        versions(v, 0, 2);
        object("a pose's mean", {"CPose2D"});
        if (v == 0) matrix("a pose's covariance", true, 3, 3);
        else skip(v == 1 ? 6 * 4 : 6 * 8);
    }

    // ---- images and cameras
    void jpeg(const char* what)
    {
        const auto n = get<uint32_t>(what);
        const size_t at = buf_.size();
        take(n, what);
        const JpegCheck check = checkJpeg(reinterpret_cast<const uint8_t*>(buf_.data() + at), n);
        // MRPT decodes the image at full size: a header claiming a huge one is refused first.
        if (check.too_large) fail(fmt::format("a colour image's JPEG header is implausible: {}", check.problem));
        if (!check.problem.empty())
            fail(fmt::format("a colour image's {} JPEG bytes are corrupt (libjpeg cannot decode them: {})", n,
                             check.problem));
    }
    void image(unsigned v)
    {
        if (v == 100)
        {
            if (flag("an image's external-storage flag")) str("an external image's file name");
            return;
        }
        versions(v, 0, 9);
        if (v == 0)
        {
            const auto w = get<uint32_t>(), h = get<uint32_t>(), channels = get<uint32_t>();
            skip(1);
            const auto length = get<uint32_t>("an image's byte count");
            checkImage("an image", w, h);
            if (channels != 1 && channels != 3) fail(fmt::format("an image of {} channels", channels));
            if (uint64_t(length) != uint64_t(w) * h * channels)
                fail(fmt::format("an image of {} x {} x {} bytes stored in {} bytes", w, h, channels, length));
            take(length, "an image's pixels");
            return;
        }
        if (v == 1)
        {
            jpeg("a colour image's JPEG");
            return;
        }
        if (v >= 6 && flag("an image's external-storage flag"))
        {
            str("an external image's file name");
            return;
        }
        if (get<uint8_t>("an image's colour flag") == 0)
        {
            const auto w = get<int32_t>(), h = get<int32_t>();
            skip(4);
            const auto size = get<int32_t>("a grey image's byte count");
            int32_t depth = 0;  // PixelDepth::D8U
            if (v >= 9) depth = get<int32_t>("a grey image's pixel depth");
            checkImage("a grey image", w, h);
            if (depth < 0 || depth > 6) fail(fmt::format("a grey image of pixel depth {}", depth));
            static constexpr int kBytes[] = {1, 1, 2, 2, 4, 4, 8};
            if (int64_t(size) != int64_t(w) * h * kBytes[depth])
                fail(fmt::format("a grey image of {} x {} pixels of {} bytes stored in {} bytes", w, h,
                                 kBytes[depth], size));
            bool zip = v == 3 || (v == 4 && size > 16 * 1024);
            if (v >= 5) zip = flag("a grey image's ZIP flag");
            if (zip) fail("a ZIP-compressed grey image, which MRPT 2.5.8 no longer reads");
            take(uint64_t(size), "a grey image's pixels");
            return;
        }
        if (v >= 7)
        {
            const auto w = get<int32_t>(), h = get<int32_t>();
            if (w < 0 && h < 0)  // v8: raw RGB
            {
                checkImage("a colour image", -int64_t(w), -int64_t(h));
                take(uint64_t(-int64_t(w)) * uint64_t(-int64_t(h)) * 3, "a colour image's pixels");
                return;
            }
            checkImage("a colour image", w, h);
            if (w == 0 || h == 0) return;  // an empty image: no pixels stored
        }
        jpeg("a colour image's JPEG");
    }
    void camera(unsigned v)
    {
        versions(v, 0, 6);
        skip(6 * 8);  // focal length (m), 5 distortion parameters
        if (v >= 3) skip(3 * 8);
        if (v < 4) matrix("a camera's intrinsic matrix", false, 3, 3);
        else skip(4 * 8);
        if (v == 0) matrix("a camera's distortion parameters", false, 1, 5);
        if (v >= 2)
        {
            const auto rows = get<uint32_t>(), cols = get<uint32_t>();
            checkImage("a camera resolution", cols, rows);
        }
        if (v >= 5) str("a camera's name");
        if (v >= 6) skip(1);
    }

    // ---- observations
    void scan3D(unsigned v)
    {
        versions(v, 0, 10);
        skip(4);  // maxRange
        object("the sensor pose", {"CPose3D"});
        const bool points = v == 0 || flag("the has-points flag");
        bool range = false;
        if (points)
        {
            const auto n = get<uint32_t>("a point count");
            if (n > io::kMaxImagePixels)
                fail(fmt::format("a point cloud of {} points, more than a reader accepts ({})", n,
                                 io::kMaxImagePixels));
            uint64_t per_point = 3 * 4;
            if (v == 0) per_point += 1;
            if (v >= 8) per_point += 2 * 2;
            take(per_point * n, "the points");
        }
        if (v >= 1)
        {
            range = flag("the has-range-image flag");
            if (v >= 9) skip(4);  // rangeUnits
            if (range)
            {
                if (v < 9)
                {
                    matrix("the range image", true, -1, -1, io::kMaxImagePixels);
                    checkRowsCols("a depth image", last_rows_, last_cols_);
                }
                else
                {
                    const auto rows = get<uint32_t>("the depth image's rows"),
                               cols = get<uint32_t>("the depth image's columns");
                    checkRowsCols("a depth image", rows, cols);
                    take(uint64_t(rows) * cols * 2, "the depth image");
                }
            }
            if (flag("the has-intensity-image flag")) object("the intensity image", {"CImage"});
            if (flag("the has-confidence-image flag")) object("the confidence image", {"CImage"});
            if (v >= 2) object("the depth camera", {"TCamera"});
            if (v >= 4)
            {
                object("the intensity camera", {"TCamera"});
                object("the intensity camera's pose", {"CPose3D"});
            }
        }
        skip(4 + 8);  // stdError, timestamp
        str("the sensor label");
        if (v >= 3)
        {
            // MRPT's load() sizes externally stored points and range images from those files
            // unchecked (and pndt reads scans through load()): such scans are refused.
            const bool external_points = flag("the external-points flag");
            str("the external points' file name");
            const bool external_range = flag("the external-range-image flag");
            str("the external range image's file name");
            if ((points && external_points) || (range && external_range))
                notChecked(fmt::format("externally stored {}", points && external_points ? "points" : "range images"),
                           "MRPT's load() would size them from that file unchecked");
        }
        if (v >= 5) flag("the range-is-depth flag");
        if (v >= 6) skip(1);  // intensity channel
        if (v >= 7 && flag("the has-pixel-labels flag")) pixelLabels();
        if (v >= 10)
        {
            const auto layers = get<uint8_t>("the number of range image layers");
            for (unsigned k = 0; k < layers; ++k)
            {
                str("a range image layer's name");
                const auto rows = get<uint32_t>("a layer's rows"), cols = get<uint32_t>("a layer's columns");
                checkRowsCols("a range image layer", rows, cols);
                take(uint64_t(rows) * cols * 2, "a range image layer");
            }
        }
    }
    void pixelLabels()
    {
        const auto version = get<uint8_t>("the pixel labels' version");
        if (version != 1) fail(fmt::format("pixel labels of version {} (MRPT 2.5.8 reads 1)", unsigned(version)));
        const auto bytes = get<uint8_t>("the pixel labels' bytes per pixel");
        if (bytes < 1 || bytes > 8) fail(fmt::format("pixel labels of {} bytes per pixel", unsigned(bytes)));
        const uint64_t element = bytes <= 2 ? bytes : bytes <= 4 ? 4 : 8;
        const auto rows = get<uint32_t>("the pixel labels' rows"), cols = get<uint32_t>("the pixel labels' columns");
        checkRowsCols("a pixel label image", rows, cols);
        take(uint64_t(rows) * cols * element, "the pixel labels");
        str("the label names' container type");
        str("the label names' key type");
        str("the label names' value type");
        const auto n = get<uint32_t>("the number of label names");
        if (n > kMaxElements) fail(fmt::format("{} label names (at most {} accepted)", n, kMaxElements));
        for (uint32_t k = 0; k < n; ++k)
        {
            skip(4);
            str("a label name");
        }
    }
    void observationImage(unsigned v)
    {
        versions(v, 0, 4);
        object("the camera pose", {"CPose3D"});
        if (v >= 4) object("the camera", {"TCamera"});
        else
        {
            matrix("the distortion parameters", true, -1, -1, 64);
            matrix("the intrinsic matrix", true, 3, 3);
        }
        object("the image", {"CImage"});
        if (v >= 1) skip(8);           // timestamp
        if (v == 2 || v == 3) skip(8);  // focal length (m)
        if (v >= 3) str("the sensor label");
    }
    void robotPose(unsigned v)
    {
        versions(v, 0, 1);
        object("the pose", {"CPose3DPDFGaussian"});
        str("the sensor label");
        skip(8);  // timestamp
        if (v >= 1) object("the sensor pose", {"CPose3D"});
    }
    void odometry(unsigned v)
    {
        versions(v, 0, 2);
        object("the odometry", {"CPose2D"});
        str("the sensor label");
        skip(8);  // timestamp
        if (v >= 1)
        {
            if (flag("the has-encoders flag") || v < 2) skip(2 * 4);
            const bool velocities = flag("the has-velocities flag");
            if (v < 2) skip(2 * 4);
            else if (velocities) skip(3 * 8);
        }
    }
    void sensoryFrame(unsigned v)
    {
        versions(v, 0, 2);
        if (v < 2) skip(4);   // ID
        if (v == 0) skip(8);  // timestamp
        const auto n = get<uint32_t>("the number of observations");
        if (n > kMaxElements)
            fail(fmt::format("a sensory frame of {} observations (at most {} accepted)", n, kMaxElements));
        for (uint32_t k = 0; k < n; ++k)
            object("an observation",
                   {"CObservation3DRangeScan", "CObservationImage", "CObservationRobotPose", "CObservationOdometry"});
    }
    void actionCollection(unsigned v)
    {
        versions(v, 0, 0);
        const auto n = get<uint32_t>("the number of actions");
        if (n > kMaxElements) fail(fmt::format("{} actions (at most {} accepted)", n, kMaxElements));
        for (uint32_t k = 0; k < n; ++k) object("an action", {"CActionRobotMovement2D"});
    }
    void motionModel(bool with_a, bool with_additional)
    {
        skip(4);                   // model selection
        skip(with_a ? 6 * 4 : 5 * 4);  // gaussian model
        const auto particles = get<int32_t>("a motion model's particle count");
        if (particles < 0 || uint32_t(particles) > kMaxParticles)
            fail(fmt::format("a motion model of {} particles (at most {} accepted)", particles, kMaxParticles));
        skip(4 * 4);
        if (with_additional) skip(2 * 4);
    }
    void robotMovement2D(unsigned v)
    {
        versions(v, 0, 7);
        const auto pdf = [&] { object("the pose change", {"CPosePDFGaussian"}); };
        if (v <= 1)
        {
            pdf();
            skip(4);  // estimation method
            if (v == 1)
            {
                flag("the has-velocities flag");
                skip(2 * 4);
                flag("the has-encoders flag");
                skip(2 * 4);
            }
            return;
        }
        const bool odometry = get<int32_t>("the estimation method") == 0;  // emOdometry
        if (odometry)
        {
            object("the odometry increment", {"CPose2D"});
            if (v == 2) skip(44);  // an old motion model, ignored
            else motionModel(v >= 4, v >= 5);
        }
        else
            pdf();
        const bool velocities = flag("the has-velocities flag");
        if (v >= 7)
        {
            if (velocities) skip(3 * 8);
        }
        else
            skip(2 * 4);
        const bool encoders = flag("the has-encoders flag");
        if (v < 7 || encoders) skip(2 * 4);
        if (v >= 6) skip(8);  // timestamp
    }

    mrpt::io::CStream& in_;
    std::string& buf_;
    const bool strict_;
    std::string first_unchecked_;  ///< the first part read by MRPT unchecked, with its context
    std::vector<std::string> context_;
    int64_t max_matrix_elements_ = 0;
    const char* matrix_what_ = "";
    int64_t last_rows_ = 0, last_cols_ = 0;
};
}  // namespace

RawlogObjectRead readCheckedRawlogObject(mrpt::io::CStream& in, std::string& bytes, bool strict,
                                         std::string& unchecked)
{
    return Walker(in, bytes, strict).top(unchecked);
}

}  // namespace pndt::app::detail
