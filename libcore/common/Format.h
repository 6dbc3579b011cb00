#pragma once
// printf-style formatting into a std::string (messages and progress lines; at most 1023 bytes).
// Declared with the printf format attribute, so the compiler checks every call's arguments
// against its format (an int printed with %.0f reads garbage: it happened).
#include <cstdarg>
#include <cstdio>
#include <string>

namespace aero {

[[gnu::format(printf, 1, 2)]] inline std::string format(const char* fmt, ...) {
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    return buf;
}

}  // namespace aero
