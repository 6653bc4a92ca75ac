// A full disk for one scope, without root: writes of regular files beyond `bytes` fail with
// EFBIG ("File too large") as a full disk fails them with ENOSPC (SIGXFSZ ignored, so the
// process is not killed). Restores the limit and the signal's handler when it ends.
#pragma once

#include <sys/resource.h>

#include <csignal>
#include <stdexcept>

namespace pndt::test_support
{
class FileSizeLimit
{
   public:
    explicit FileSizeLimit(rlim_t bytes)
    {
        if (getrlimit(RLIMIT_FSIZE, &before_) != 0) throw std::runtime_error("getrlimit(RLIMIT_FSIZE) failed");
        handler_ = std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit = before_;
        limit.rlim_cur = bytes;
        if (setrlimit(RLIMIT_FSIZE, &limit) != 0) throw std::runtime_error("setrlimit(RLIMIT_FSIZE) failed");
    }
    ~FileSizeLimit()
    {
        setrlimit(RLIMIT_FSIZE, &before_);
        std::signal(SIGXFSZ, handler_);
    }
    FileSizeLimit(const FileSizeLimit&) = delete;
    FileSizeLimit& operator=(const FileSizeLimit&) = delete;

   private:
    rlimit before_{};
    void (*handler_)(int) = SIG_DFL;
};
}  // namespace pndt::test_support
