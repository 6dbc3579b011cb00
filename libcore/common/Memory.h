#pragma once
// Memory use of this process, from /proc/self/status (Linux): the resident set now and its peak
// (VmRSS, VmHWM), in MiB; 0 where the file is unavailable.
#include <cstdio>
#include <cstring>

namespace aero {

inline double procStatusMb(const char* key) {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    double kb = 0;
    const std::size_t n = std::strlen(key);
    while (std::fgets(line, sizeof line, f)) {
        if (std::strncmp(line, key, n) == 0 && line[n] == ':') {
            std::sscanf(line + n + 1, "%lf", &kb);
            break;
        }
    }
    std::fclose(f);
    return kb / 1024.0;
}

inline double peakMemoryMb() { return procStatusMb("VmHWM"); }
inline double currentMemoryMb() { return procStatusMb("VmRSS"); }

}  // namespace aero
