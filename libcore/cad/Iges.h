#pragma once
// IGES import and export. This header exposes no OpenCASCADE type: the file's text is read by
// our own parser (cad/IgesText.h), so B-spline surfaces (128) and trimmed surfaces over them
// (144/142 with parameter-space curves 126, 110, 102) come in bit for bit as written, in the
// file's own unit; other surfaces go through OpenCASCADE (cad/Occt.h) in that same unit.
#include <string>

#include "cad/ReadReport.h"
#include "geometry/PatchSet.h"

namespace aero::cad {

/// Reads every surface of the file as a NURBS patch, with its trimming loops in parameter space
/// when the file trims it, coordinates in the file's unit (set.unit; nothing is scaled).
/// `report` (optional) receives what became of each entity (kept, converted, trimmed, ignored and
/// why) and warnings for every change to the geometry. Throws InputError naming the file when it
/// is missing, not IGES or has no surfaces, and naming the entity (with its directory line) for
/// malformed entities; GeometryError naming the entity for invalid knots or coordinates.
/// OpenCASCADE's console output is kept off stdout.
geometry::PatchSet readIges(const std::string& path, ReadReport* report = nullptr);

/// Writes the patches in set.unit (millimetres, unit flag 2, when the set states none): an
/// untrimmed patch as entity 128, a trimmed one as a 144 over its 128 with each loop a 142
/// whose parameter-space curve is a 126 (or a 102 of 126s); no model-space trim curves (the
/// 142's preference says "parameter space"). Reals with 17 significant digits, so reading the file
/// back gives the same poles, weights, knots and trim curves bit for bit. Names longer than the
/// 8-character label go in a name property (406 form 15). Written atomically; throws InputError if
/// the file cannot be written, GeometryError for an invalid set.
void writeIges(const geometry::PatchSet& set, const std::string& path);

}  // namespace aero::cad
