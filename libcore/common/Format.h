#pragma once
// printf-style formatting into a std::string (messages and progress lines; at most 1023 bytes).
#include <cstdio>
#include <string>

namespace aero {

inline std::string format(const char* fmt, auto... args) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, fmt, args...);
    return buf;
}

}  // namespace aero
