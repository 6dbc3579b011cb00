#pragma once
// Reading and writing a case's geometry by file extension: the one loader the CLI, the batch mode
// and the GUI use (native JSON patch sets, IGES and STEP through aeroform_cad).
#include <string>

#include "cad/ReadReport.h"
#include "geometry/PatchSet.h"

namespace aero::study {

/// The kind of a geometry file: by extension (.json, .igs/.iges, .stp/.step, any case), else
/// sniffed from its first bytes (JSON starts with '{', STEP with "ISO-10303-21;", else IGES).
enum class GeometryFormat { Json, Iges, Step };
GeometryFormat geometryFormat(const std::string& path);

/// Reads a patch set in the file's own unit and with its trims (see cad/Iges.h, cad/Step.h).
/// `report` (optional) receives what was read, converted or ignored (for JSON: one kept item per
/// patch). Throws InputError naming the file, GeometryError naming the entity.
geometry::PatchSet loadGeometry(const std::string& path, cad::ReadReport* report = nullptr);

/// Writes .json, .igs/.iges or .stp/.step (AP214) by extension, in set.unit; InputError for
/// anything else.
void saveGeometry(const geometry::PatchSet& set, const std::string& path);

/// Lower-case extension without the dot ("" if none).
std::string fileExtension(const std::string& path);

}  // namespace aero::study
