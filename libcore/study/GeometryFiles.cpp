#include "study/GeometryFiles.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "cad/Iges.h"
#include "cad/Step.h"
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

GeometryFormat geometryFormat(const std::string& path) {
    const std::string ext = fileExtension(path);
    if (ext == "json") return GeometryFormat::Json;
    if (ext == "igs" || ext == "iges") return GeometryFormat::Iges;
    if (ext == "stp" || ext == "step") return GeometryFormat::Step;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open geometry file '" + path + "'");
    std::string head(64, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const std::size_t start = head.find_first_not_of(" \t\r\n");
    if (start != std::string::npos && head[start] == '{') return GeometryFormat::Json;
    if (start != std::string::npos && head.compare(start, 13, "ISO-10303-21;") == 0) return GeometryFormat::Step;
    return GeometryFormat::Iges;
}

geometry::PatchSet loadGeometry(const std::string& path, cad::ReadReport* report) {
    io::checkInputFile(path, "geometry file", std::uintmax_t(2) << 30);
    switch (geometryFormat(path)) {
        case GeometryFormat::Iges:
            return cad::readIges(path, report);
        case GeometryFormat::Step:
            return cad::readStep(path, report);
        case GeometryFormat::Json:
            break;
    }
    geometry::PatchSet set = io::readPatchSetJson(path);
    if (report) {
        *report = {};
        report->format = "JSON";
        report->unit = set.unit;
        report->unitSource = set.unit.empty() ? "no \"unit\" key" : "the \"unit\" key";
        for (int p = 0; p < set.size(); ++p) {
            cad::ReadItem item;
            item.entity = p + 1;
            item.kind = "patch";
            item.surface = cad::SurfaceOutcome::Kept;
            item.trim = set.trimmed(p) ? cad::TrimOutcome::Kept : cad::TrimOutcome::None;
            item.patches = {p};
            report->items.push_back(std::move(item));
        }
    }
    return set;
}

void saveGeometry(const geometry::PatchSet& set, const std::string& path) {
    const std::string ext = fileExtension(path);
    if (ext == "json") {
        io::writePatchSetJson(set, path);
    } else if (ext == "igs" || ext == "iges") {
        cad::writeIges(set, path);
    } else if (ext == "stp" || ext == "step") {
        cad::writeStep(set, path);
    } else {
        throw InputError("output file '" + path + "': unknown extension (use .json, .igs, .iges, .stp or .step)");
    }
}

}  // namespace aero::study
