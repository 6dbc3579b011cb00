#pragma once
// Checks on a file before it is read (issue #20): a directory, a device (/dev/zero) or a file far
// larger than its kind can be is refused with the path and the reason, instead of being read
// until memory runs out or reported as "not valid JSON".
#include <cstdint>
#include <string>

namespace aero::io {

/// Throws InputError naming `what` ("case file", ...) and the path when the path does not exist,
/// is not a regular file, or is larger than maxBytes.
void checkInputFile(const std::string& path, const char* what, std::uintmax_t maxBytes);

}  // namespace aero::io
