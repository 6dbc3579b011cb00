#pragma once
// IGES import and export through OpenCASCADE. This header exposes no OpenCASCADE type; the
// adapter (cad/Iges.cpp) is the only translation unit of the project that includes OCCT.
#include <string>
#include <vector>

#include "geometry/PatchSet.h"

namespace aero::cad {

struct IgesReadReport {
    int faces = 0;              // faces / surfaces found in the file
    int converted = 0;          // non-B-spline surfaces converted to B-splines by OCCT
    int trimmed = 0;            // trimmed faces whose underlying (untrimmed) surface was taken
    std::vector<std::string> warnings;
};

/// Reads every B-spline surface (entity 128, or faces of shells whose surfaces are or convert
/// to B-splines). Throws InputError naming the file when it is missing, not IGES, or has no
/// surfaces, and GeometryError naming the entity for invalid knots or coordinates.
/// OpenCASCADE's console output is kept off stdout.
geometry::PatchSet readIges(const std::string& path, IgesReadReport* report = nullptr);

/// Writes each patch as an IGES entity 128 with 17 significant digits, so that reading the
/// file back gives the same poles, weights and knots bit for bit. Throws InputError if the
/// file cannot be written.
void writeIges(const geometry::PatchSet& set, const std::string& path);

}  // namespace aero::cad
