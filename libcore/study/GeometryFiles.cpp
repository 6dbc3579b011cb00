#include "study/GeometryFiles.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "common/Error.h"
#include "io/InputFile.h"
#include "io/PatchSetJson.h"

namespace aero::study {

std::string fileExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

geometry::PatchSet loadGeometry(const std::string& path, cad::IgesReadReport* report) {
    io::checkInputFile(path, "geometry file", std::uintmax_t(2) << 30);
    std::string ext = fileExtension(path);
    if (ext != "json" && ext != "igs" && ext != "iges") {
        std::ifstream in(path);
        if (!in) throw InputError("cannot open geometry file '" + path + "'");
        char c = ' ';
        while (in.get(c) && std::isspace(static_cast<unsigned char>(c))) {
        }
        ext = c == '{' ? "json" : "igs";
    }
    if (ext == "json") return io::readPatchSetJson(path);
    return cad::readIges(path, report);
}

void saveGeometry(const geometry::PatchSet& set, const std::string& path) {
    const std::string ext = fileExtension(path);
    if (ext == "json") {
        io::writePatchSetJson(set, path);
    } else if (ext == "igs" || ext == "iges") {
        cad::writeIges(set, path);
    } else {
        throw InputError("output file '" + path + "': unknown extension (use .json, .igs or .iges)");
    }
}

}  // namespace aero::study
