#include <fmt/format.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <pndt/app/observation_stream.h>
#include <pndt/io/images.h>

#include "gz_file_input.h"
#include "rawlog_object_check.h"

#include <algorithm>
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
/// Objects are read from it by readCheckedRawlogObject() (rawlog_object_check.h), which
/// bounds every size MRPT would allocate from and refuses colour images whose JPEG bytes
/// libjpeg cannot decode (MRPT's libjpeg error handler calls exit()), before MRPT parses
/// the checked bytes from memory.
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
        return got;
    }
    size_t Write(const void*, size_t) override { throw std::logic_error("ObservationStream is read-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error("ObservationStream cannot seek"); }
    uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
    uint64_t getPosition() const override { return position_; }

   private:
    GzFileInput& in_;
    uint64_t position_ = 0, object_start_ = 0;
};

ObservationStream::ObservationStream(const std::string& path, UncheckedObjects unchecked)
    : path_(path), unchecked_(unchecked)
{
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(fmt::format("{}: no such file", path));
    file_ = std::make_unique<GzFileInput>(path);
    input_ = std::make_unique<GuardedInput>(*file_);
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
            // The object's layout is walked and its sizes checked while its bytes are
            // collected (a part it has no layout for is read by MRPT's own reader on the way);
            // MRPT then parses the collected bytes from memory.
            std::string unchecked_part;
            const auto read = detail::readCheckedRawlogObject(
                *input_, object_bytes_, unchecked_ == UncheckedObjects::Refused, unchecked_part);
            if (read == detail::RawlogObjectRead::End)
            {
                ended_ = true;  // clean end between objects
                return nullptr;
            }
            if (read == detail::RawlogObjectRead::Unchecked)
            {
                ++unchecked_objects_;
                if (unchecked_reported_.insert(unchecked_part).second)
                    fmt::print(stderr,
                               "{}: object #{}: {}, whose sizes this reader does not check: MRPT reads it as it "
                               "is (said once)\n",
                               path_, objects_ + 1, unchecked_part);
            }
            mrpt::io::CMemoryStream memory;
            memory.assignMemoryNotOwn(object_bytes_.data(), object_bytes_.size());
            auto archive = mrpt::serialization::archiveFrom(memory);
            try
            {
                archive >> obj;
            }
            catch (const mrpt::serialization::CExceptionEOF&)
            {
                throw std::runtime_error("MRPT read past the object's checked bytes");
            }
            if (memory.getPosition() != object_bytes_.size())
                throw std::runtime_error(fmt::format("MRPT read {} of the object's {} checked bytes",
                                                     memory.getPosition(), object_bytes_.size()));
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
