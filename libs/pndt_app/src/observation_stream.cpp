#include <fmt/format.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <opencv2/imgcodecs.hpp>
#include <pndt/app/observation_stream.h>
#include <pndt/io/images.h>

#include "gz_file_input.h"

#include <cstdint>
#include <cstring>
#include <filesystem>

namespace pndt::app
{
/// The decompressed file, where a short or failed read inside an object throws
/// (only a read of nothing at an object's start is the clean end of the file).
/// MRPT's gz stream returns gzread's -1 (a cut or corrupt gzip) as a huge byte
/// count, and CImage ignores a short read of a colour image's JPEG bytes and
/// decodes the half-filled buffer, where libjpeg's default error handler calls
/// exit() ("Bogus marker length"): thrown here, the cut shows as a truncated file.
/// Whole but corrupt JPEG bytes reach the same exit() ("Quantization table 0x00
/// was not defined"): a colour image's bytes (CImage reads a 4-byte length, then
/// that many bytes starting with the JPEG SOI marker) are first decoded here at
/// 1/8 scale by OpenCV, through the same libjpeg with an error handler that
/// returns; what it cannot decode is thrown as a corrupt image.
class ObservationStream::GuardedInput : public mrpt::io::CStream
{
   public:
    explicit GuardedInput(GzFileInput& in) : in_(in) {}
    void startObject() { object_start_ = position_; }

    size_t Read(void* buffer, size_t count) override
    {
        const size_t got = in_.Read(buffer, count);
        if (got > count) throw std::runtime_error("the compressed data ends early or is corrupt");
        position_ += got;
        if (got < count && !(got == 0 && position_ == object_start_))
            throw std::runtime_error(fmt::format("the file ends {} bytes into the object", position_ - object_start_));
        const auto* bytes = static_cast<const uint8_t*>(buffer);
        if (count == last_length_ && count >= 2 && count <= size_t(INT32_MAX) && bytes[0] == 0xFF && bytes[1] == 0xD8)
        {
            // MRPT decodes the image at full size: a header claiming a huge one is refused first.
            const auto wh = pndt::io::imageHeaderSize(bytes, count);
            if (const std::string problem = pndt::io::imageSizeProblem(wh[0], wh[1]); !problem.empty())
                throw std::runtime_error(fmt::format("a colour image's JPEG header is implausible: {}", problem));
        }
        if (count == last_length_ && count >= 2 && count <= size_t(INT32_MAX) && bytes[0] == 0xFF && bytes[1] == 0xD8 &&
            !decodes(bytes, count))
            throw std::runtime_error(
                fmt::format("a colour image's {} JPEG bytes are corrupt (libjpeg cannot decode them)", count));
        uint32_t length = 0;
        if (got == sizeof(length)) std::memcpy(&length, buffer, sizeof(length));  // rawlogs are little-endian
        last_length_ = got == sizeof(length) ? length : ~uint64_t(0);
        return got;
    }
    size_t Write(const void*, size_t) override { throw std::logic_error("ObservationStream is read-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error("ObservationStream cannot seek"); }
    uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
    uint64_t getPosition() const override { return position_; }

   private:
    static bool decodes(const uint8_t* bytes, size_t count)
    {
        const cv::Mat encoded(1, int(count), CV_8UC1, const_cast<uint8_t*>(bytes));
        try
        {
            return !cv::imdecode(encoded, cv::IMREAD_REDUCED_COLOR_8).empty();
        }
        catch (const cv::Exception&)
        {
            return false;
        }
    }

    GzFileInput& in_;
    uint64_t position_ = 0, object_start_ = 0;
    uint64_t last_length_ = ~uint64_t(0);  ///< the value of the last read if it was 4 bytes
};

ObservationStream::ObservationStream(const std::string& path) : path_(path)
{
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(fmt::format("{}: no such file", path));
    file_ = std::make_unique<GzFileInput>(path);
    input_ = std::make_unique<GuardedInput>(*file_);
    archive_ = std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CStream>>(*input_);
}

ObservationStream::~ObservationStream() = default;

double ObservationStream::progress() const
{
    const uint64_t total = file_->getTotalBytesCount();
    return total ? std::min(1.0, double(file_->compressedPosition()) / double(total)) : 1.0;
}

mrpt::obs::CObservation::Ptr ObservationStream::next()
{
    while (true)
    {
        if (!queued_.empty())
        {
            auto o = queued_.front();
            queued_.pop_front();
            return o;
        }
        if (ended_) return nullptr;
        mrpt::serialization::CSerializable::Ptr obj;
        const uint64_t at = input_->getPosition();
        input_->startObject();
        try
        {
            *archive_ >> obj;
        }
        catch (const mrpt::serialization::CExceptionEOF&)
        {
            ended_ = true;  // clean end between objects
            return nullptr;
        }
        catch (const std::exception& e)
        {
            std::string cause = e.what();
            // MRPT nests the exceptions of the objects being parsed, each with its
            // source location and backtrace: keep the innermost message.
            constexpr const char* kInner = "Original exception:";
            if (const auto p = cause.rfind(kInner); p != std::string::npos) cause.erase(0, p + std::strlen(kInner));
            for (const char* tail : {"Location:", "Call stack", "==== MRPT"})
                if (const auto p = cause.find(tail); p != std::string::npos) cause.resize(p);
            if (const auto p = cause.find("Message:"); p != std::string::npos) cause.erase(0, p + 8);
            const auto first = cause.find_first_not_of(" \n");
            cause.erase(0, first == std::string::npos ? cause.size() : first);
            while (!cause.empty() && (cause.back() == '\n' || cause.back() == ' ')) cause.pop_back();
            ended_ = truncated_ = true;
            stop_reason_ = fmt::format("{}: truncated or corrupt at object #{} (it starts at decompressed "
                                       "byte {}; the file has {} bytes): {}",
                                       path_, objects_ + 1, at, file_->getTotalBytesCount(), cause);
            return nullptr;
        }
        ++objects_;
        if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) return o;
        if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj))
            for (const auto& o : *sf) queued_.push_back(o);
        // Actions (odometry increments) and other objects carry nothing we map.
    }
}

}  // namespace pndt::app
