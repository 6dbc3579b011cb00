#include "io/InputFile.h"

#include <filesystem>

#include "common/Error.h"

namespace aero::io {

void checkInputFile(const std::string& path, const char* what, std::uintmax_t maxBytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec || !fs::exists(st)) throw InputError(std::string("cannot open ") + what + " '" + path + "': no such file");
    if (fs::is_directory(st)) throw InputError(std::string("'") + path + "' is a directory, not a " + what);
    if (!fs::is_regular_file(st)) throw InputError(std::string("'") + path + "' is not a regular file (a " + what + " must be one)");
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > maxBytes) {
        throw InputError(std::string("'") + path + "' has " + std::to_string(size) + " bytes, more than the " +
                         std::to_string(maxBytes) + " a " + what + " may have");
    }
}

}  // namespace aero::io
