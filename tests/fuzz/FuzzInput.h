#pragma once
// Shared by the fuzz targets (tests/fuzz): the outcome every target accepts and, for readers that
// take a path, the input as a file. A target calls its reader and catches aero::Error (the
// documented "clear error" path); anything else escaping, a crash or a sanitizer report is a
// finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace aero::fuzz {

/// Writes the input to this process's own file "<dir>/aeroform-fuzz-<pid><ext>" (dir: $TMPDIR,
/// else /dev/shm when present, else /tmp), overwriting the previous input, and returns its path.
/// Aborts if the file cannot be written (a broken setup, not a finding in the reader).
inline std::string inputFile(const std::uint8_t* data, std::size_t size, const char* ext) {
    static const std::string path = [ext] {
        const char* env = std::getenv("TMPDIR");
        std::string dir = env && *env ? env : (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
        return dir + "/aeroform-fuzz-" + std::to_string(getpid()) + ext;
    }();
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
        std::perror(path.c_str());
        std::abort();
    }
    return path;
}

inline std::string text(const std::uint8_t* data, std::size_t size) {
    return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace aero::fuzz
