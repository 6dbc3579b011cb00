#pragma once
// Reading and writing a case's geometry by file extension: the one loader the CLI, the batch mode
// and the GUI use (native JSON patch sets, IGES through aeroform_cad).
#include <string>

#include "cad/Iges.h"
#include "geometry/PatchSet.h"

namespace aero::study {

/// Reads a patch set from .json (native) or .igs/.iges; other names are sniffed (JSON starts
/// with '{'). `report` (optional) receives what the IGES reader converted or trimmed. Throws
/// InputError naming the file, GeometryError naming the entity.
geometry::PatchSet loadGeometry(const std::string& path, cad::IgesReadReport* report = nullptr);

/// Writes .json or .igs/.iges by extension; InputError for anything else.
void saveGeometry(const geometry::PatchSet& set, const std::string& path);

/// Lower-case extension without the dot ("" if none).
std::string fileExtension(const std::string& path);

}  // namespace aero::study
