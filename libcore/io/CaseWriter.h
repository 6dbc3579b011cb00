#pragma once
// Writing case files (`aeroform.case`, version 1): the inverse of io::parseCase, so that a
// project edited in the GUI is a case the CLI runs (`aeroform-cli deform PROJECT.json`).
//
// Round trip: parseCase(formatCase(c), c.path) reproduces every field of c exactly (numbers are
// written in shortest round-trip form) provided c is in the form parseCase produces: paths
// lexically normal, station prefixes equal to their lattice's name, displacement and point
// indices within the lattices' (unrefined) counts. Keys at their default value are written
// anyway where that documents the case (counts, degrees, padding; every mesh option when the
// case has a mesh section); optional ones are omitted when absent or empty (box, patches,
// refine, crease, mesh, output, values, displacements).
#include <string>

#include "io/CaseFile.h"

namespace aero::io {

/// The case as JSON text. Paths (geometry, outputs) are written relative to the folder of
/// c.path when both are absolute and share their first folder (e.g. /home/...), else as given;
/// with an empty c.path they are written as given. Lattices are referred to by name.
/// Throws CaseError on references to lattices that do not exist (naming the key).
std::string formatCase(const CaseFile& c);

/// Writes formatCase(c) with c.path replaced by `path` (so relative paths are relative to the
/// new location): to `path`.tmp first, then renamed over `path`, so a reader never sees a
/// half-written project. Throws InputError naming the file if it cannot be written.
void writeCase(const CaseFile& c, const std::string& path);

}  // namespace aero::io
