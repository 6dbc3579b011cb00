#pragma once
// STEP (AP214 / AP242) import and export through OpenCASCADE's STEP translator. This header
// exposes no OpenCASCADE type.
#include <string>

#include "cad/ReadReport.h"
#include "geometry/PatchSet.h"

namespace aero::cad {

/// Reads every face of a STEP file as a NURBS patch in the file's own length unit (set.unit;
/// nothing is scaled). B-spline surfaces come in as written; other surfaces are converted to exact
/// NURBS by OpenCASCADE. A face bounded by less than its whole surface keeps its boundary as
/// parameter-space loops (OpenCASCADE's p-curves: the file's own when it has them, else computed
/// from the model-space edges; the report gives their largest distance from those edges).
/// `report` (optional) receives one item per face. Throws InputError naming the file when it is
/// missing, not STEP or has no faces.
geometry::PatchSet readStep(const std::string& path, ReadReport* report = nullptr);

/// Writes the patches as B-spline faces (trimmed ones bounded by their loops, with the p-curves
/// and model-space edge curves computed by OpenCASCADE) in `schema` "AP214" or "AP242", length
/// unit set.unit (millimetres when the set states none), reals with 17 significant digits (so
/// poles, weights and knots read back bit for bit). Written atomically; throws InputError if the
/// file cannot be written or the schema is unknown, GeometryError naming a patch OpenCASCADE
/// refuses.
void writeStep(const geometry::PatchSet& set, const std::string& path,
               const std::string& schema = "AP214");

}  // namespace aero::cad
