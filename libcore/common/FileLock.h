#pragma once
// An exclusive lock on a file that one process at a time may own (e.g. an optimization's
// history): a flock on a lock file, held while the object lives. The kernel releases it when the
// process ends in any way (kill -9, a power cut), so a killed owner never leaves a stale lock.
// The file carries the owner's process id, for the message of the one refused.
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/file.h>
#include <unistd.h>

#include "common/Error.h"

namespace aero {

class FileLock {
public:
    /// Tries to take the lock on `path` (created if missing). Throws InputError when the file
    /// cannot be created or locked for another reason than a holder.
    explicit FileLock(const std::string& path) {
        fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw InputError("cannot create the lock file '" + path + "': " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            const int e = errno;
            char buf[32] = {};
            const ssize_t got = ::pread(fd_, buf, sizeof buf - 1, 0);
            ::close(fd_);
            fd_ = -1;
            if (e != EWOULDBLOCK) throw InputError("cannot lock '" + path + "': " + std::strerror(e));
            if (got > 0) owner_.assign(buf, static_cast<std::size_t>(got));
            return;
        }
        const std::string pid = std::to_string(::getpid());
        if (::ftruncate(fd_, 0) == 0) {
            const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
            (void)written;  // the id is only for the message: the lock holds without it
        }
    }
    ~FileLock() {
        if (fd_ >= 0) ::close(fd_);  // releases the lock
    }
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

    /// Whether this object holds the lock.
    bool held() const { return fd_ >= 0; }
    /// When not held: the holder's process id as it wrote it (empty if unknown).
    const std::string& owner() const { return owner_; }

private:
    int fd_ = -1;
    std::string owner_;
};

}  // namespace aero
