#pragma once
// Writing a file so that a failure never costs the user the file that was there (issue #20): the
// data goes to a temporary file next to the target, which is renamed over it only once complete.
// A symlink is followed: its target is replaced and the link stays a link. Without commit() the
// temporary file is removed.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <signal.h>
#include <system_error>
#include <unistd.h>

#include "common/Error.h"

namespace aero {

class AtomicFile {
public:
    /// `what` names the file for messages ("IGES file", "patch-set file").
    AtomicFile(const std::string& path, const std::string& what) : path_(path), what_(what) {
        namespace fs = std::filesystem;
        std::error_code ec;
        target_ = fs::path(path);
        if (fs::is_symlink(fs::symlink_status(target_, ec))) {
            const fs::path to = fs::read_symlink(target_, ec);
            if (!ec) target_ = to.is_absolute() ? to : target_.parent_path() / to;
        }
        if (fs::is_directory(target_, ec)) throw InputError("cannot write " + what_ + " '" + path_ + "': it is a directory");
        temporary_ = target_.string() + ".tmp" + std::to_string(::getpid());
        removeOrphans();
    }
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    ~AtomicFile() {
        if (!committed_) {
            std::error_code ec;
            std::filesystem::remove(temporary_, ec);
        }
    }

    /// Where to write the data.
    const std::string& temporary() const { return temporary_; }

    /// Renames the temporary file over the target (or the symlink's target).
    void commit() {
        std::error_code ec;
        std::filesystem::rename(temporary_, target_, ec);
        if (ec) throw InputError("cannot replace " + what_ + " '" + path_ + "': " + ec.message());
        committed_ = true;
    }

    /// "cannot write <what> '<path>': <errno text>" for a failed write.
    [[noreturn]] void fail() const {
        throw InputError("cannot write " + what_ + " '" + path_ + "': " + std::strerror(errno ? errno : EIO));
    }

private:
    // Temporary files of this target left by a process that was killed while writing (kill -9,
    // a power cut): removed, so they do not pile up next to the file. Only those whose process
    // no longer exists; another live writer's file is left alone.
    void removeOrphans() const {
        namespace fs = std::filesystem;
        std::error_code ec;
        const std::string prefix = target_.filename().string() + ".tmp";
        const fs::path dir = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string name = it->path().filename().string();
            if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
            const std::string digits = name.substr(prefix.size());
            if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
            const pid_t pid = static_cast<pid_t>(std::stol(digits));
            if (pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) {
                std::error_code rm;
                fs::remove(it->path(), rm);
            }
        }
    }

    std::string path_, what_;
    std::filesystem::path target_;
    std::string temporary_;
    bool committed_ = false;
};

/// Writes `text` to `path` through an AtomicFile (binary, so the bytes are exactly `text`).
inline void writeTextAtomically(const std::string& path, const std::string& text, const std::string& what) {
    AtomicFile file(path, what);
    {
        errno = 0;
        std::ofstream out(file.temporary(), std::ios::binary | std::ios::trunc);
        if (!out) file.fail();
        out << text;
        if (!out.flush()) file.fail();
    }
    file.commit();
}

}  // namespace aero
