#pragma once
// A case's first FFD level, checked: the model, the design values, the moved lattices, the
// deformed geometry and its unique control points (the wall of the mesh control grid). Shared
// by aeroform-cli, `aeroform --batch` and the GUI, so all of them refuse the same bad input.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ffd/Injectivity.h"
#include "io/CaseFile.h"

namespace aero::study {

/// Progress lines for a human ("embedded 521 of 521 ..."); may be empty.
using Log = std::function<void(const std::string&)>;

struct CaseShape {
    std::unique_ptr<ffd::FfdModel> model;           // null if the case has no lattices
    std::vector<double> values;                      // design-variable values
    std::vector<ffd::Lattice> moved;                 // B(v) plus displacements, one per lattice
    std::vector<ffd::InjectivityReport> injectivity; // one per lattice
    geometry::PatchSet deformed;                     // the deformed geometry (baseline if no lattices)
    std::vector<double> uniqueSurface;               // its unique control points, 3 each
    int pointsOutside = 0, pointsNotConverged = 0;
};

/// Builds and checks the first level. Throws GeometryError naming the case if control points
/// cannot be embedded (unless embedding.allow_outside) or a moved lattice is not injective (with
/// the lattice name and location); CaseError for bad values. The failures are also logged.
CaseShape deformCase(const io::CaseFile& c, const geometry::PatchSet& geometry, const Log& log = {});

}  // namespace aero::study
