// STEP import and export (see Step.h): the report around OpenCASCADE's translator (cad/Occt.h).
#include "cad/Step.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cad/Occt.h"
#include "cad/StepText.h"
#include "common/Error.h"

namespace aero::cad {

namespace {

std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

/// A file that does not start like STEP ("ISO-10303-21;") is refused before OpenCASCADE sees it,
/// and so is one whose exchange structure is not well formed (cad/StepText.h: OpenCASCADE's loader
/// crashes on some).
void checkStepText(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError("cannot open STEP file '" + path + "': is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open STEP file '" + path + "': " + std::strerror(errno));
    std::string head(4096, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    const std::size_t start = head.find_first_not_of(" \t\r\n");
    if (start == std::string::npos || head.compare(start, 13, "ISO-10303-21;") != 0)
        throw InputError("'" + path +
                         "' is not a STEP file (it does not start with ISO-10303-21;)");
    // The rest of the file after the head already read, in one go.
    std::ostringstream rest;
    if (in) rest << in.rdbuf();
    if (in.bad()) throw InputError("cannot read STEP file '" + path + "': " + std::strerror(errno));
    step::checkExchangeStructure(head + std::move(rest).str(), path);
}

}  // namespace

geometry::PatchSet readStep(const std::string& path, ReadReport* report) {
    ReadReport local;
    ReadReport& rep = report ? *report : local;
    rep = {};
    rep.format = "STEP";
    checkStepText(path);
    occt::StepFile file = occt::readStepIsolated(path);
    rep.unit = file.unit;
    rep.unitSource = file.unitName.empty() ? "no length unit in the file"
                                           : "STEP length unit '" + file.unitName + "'";
    rep.warnings = file.warnings;
    rep.notes = file.notes;

    geometry::PatchSet set;
    set.source = path;
    set.unit = file.unit;
    for (std::size_t k = 0; k < file.faces.size(); ++k) {
        occt::Face& f = file.faces[k];
        ReadItem item;
        item.entity = f.stepId;
        item.kind = "face on a " + (f.surfaceType.rfind("Geom_", 0) == 0 ? f.surfaceType.substr(5)
                                                                         : f.surfaceType);
        item.surface = f.converted ? SurfaceOutcome::Converted : SurfaceOutcome::Kept;
        const std::string what = "face " + std::to_string(k + 1) +
                                 (f.stepId ? " (#" + std::to_string(f.stepId) + ")" : "");
        std::string note = f.conversion;
        if (f.surfaceType == "Geom_OffsetSurface")
            rep.warnings.push_back(what + ": an offset surface, approximated by a NURBS surface");
        if (!f.trimProblem.empty()) {
            item.trim = TrimOutcome::Dropped;
            rep.warnings.push_back(
                what + ": trimming dropped, the whole base surface is used: " + f.trimProblem);
        } else if (f.trim.trimmed()) {
            item.trim = TrimOutcome::Computed;
            note += std::string(note.empty() ? "" : "; ") +
                    "trim loops from OpenCASCADE's p-curves: largest distance " +
                    number(f.trimDeviation) + " from the model-space edges";
            // As for IGES: loops further than 1e-9 of the patch's size from the edges change the
            // geometry.
            double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL},
                   hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
            for (std::size_t a = 0; a < f.patch.points.size(); ++a) {
                lo[a % 3] = std::min(lo[a % 3], f.patch.points[a]);
                hi[a % 3] = std::max(hi[a % 3], f.patch.points[a]);
            }
            if (f.trimDeviation > 1e-9 * std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]))
                rep.warnings.push_back(
                    what + ": trim loops from OpenCASCADE's p-curves, largest distance " +
                    number(f.trimDeviation) + " from the model-space edges");
        }
        item.note = note;
        set.patches.push_back(std::move(f.patch));
        set.trims.push_back(std::move(f.trim));
        set.names.push_back(f.stepId ? "face #" + std::to_string(f.stepId)
                                     : "face " + std::to_string(k + 1));
        item.patches.push_back(set.size() - 1);
        rep.items.push_back(std::move(item));
    }
    if (set.patches.empty()) throw InputError("STEP file '" + path + "' has no faces");
    if (set.trimmedCount() == 0) set.trims.clear();
    geometry::validate(set);
    return set;
}

void writeStep(const geometry::PatchSet& set, const std::string& path, const std::string& schema) {
    if (schema != "AP214" && schema != "AP242")
        throw InputError("STEP schema '" + schema + "' unknown (AP214 or AP242)");
    occt::writeStep(set, path, schema);
}

}  // namespace aero::cad
