#pragma once
// The bridge to OpenCASCADE (internal to aeroform_cad): plain data in and out, so that Occt.cpp
// is the one translation unit of the project that includes OCCT headers.
#include <string>
#include <vector>

#include "geometry/PatchSet.h"

namespace aero::cad::occt {

/// One OpenCASCADE face as a NURBS patch with its trimming in the patch's parameter space.
struct Face {
    geometry::Patch patch;
    geometry::PatchTrim trim;  // not trimmed() when the face covers its whole surface
    std::string surfaceType;   // the face's surface before conversion: "Geom_BSplineSurface",
                               // "Geom_Plane", ...
    bool converted =
        false;  // not a B-spline in the source, or re-knotted / moved (computed control points)
    std::string conversion;  // what was done, for the report
    double trimDeviation =
        0;  // largest distance between S(p-curve) and the edges' model-space curves
    std::string
        trimProblem;  // non-empty: the loops could not be kept (the reason); trim is then empty
    int stepId = 0;   // STEP: the #id of the face entity (0 if unknown)
};

/// The faces an entity became, or why none.
struct EntityFaces {
    std::vector<Face> faces;
    std::string failure;  // OpenCASCADE's reason when it built nothing
};

/// Reads the IGES file `path` with OpenCASCADE in the file's own unit (`occtUnit`: an
/// xstep.cascade.unit name such as "MM", "M", "INCH", so nothing is scaled) and transfers the
/// entities with these directory entries, one result per entry. `projectEdges[k]`: the entity's
/// trims are in model space only, so its p-curves are also projected to 1e-10 of the patch size
/// and the closer of OpenCASCADE's and ours is kept. OpenCASCADE's console output is kept off
/// stdout. Throws InputError naming the file if OpenCASCADE cannot read it.
std::vector<EntityFaces> transferIgesEntities(const std::string& path, const std::string& occtUnit,
                                              const std::vector<int>& directoryEntries,
                                              const std::vector<char>& projectEdges);

struct StepFile {
    std::vector<Face> faces;
    std::string unit;      // canonical unit of the file's length unit ("" if none found)
    std::string unitName;  // as OpenCASCADE names it ("millimetre", "INCH", ...)
    std::vector<std::string> notes;
    std::vector<std::string> warnings;
    int roots = 0;
};

/// Reads every face of a STEP file in the file's own length unit (no scaling); p-curves that lie
/// further than 1e-12 of a patch's size from their edges are projected again (see above) and
/// the closer kept. Throws InputError
/// naming the file if it is not STEP or has no shape.
StepFile readStep(const std::string& path);

/// transferIgesEntities and readStep where cad::occtIsolation() says (cad/OcctProcess.h): in the
/// helper process when there is one, else here. The same results to the bit; a crash or a hang of
/// OpenCASCADE in the helper is an InputError naming the file.
std::vector<EntityFaces> transferIgesEntitiesIsolated(const std::string& path, const std::string& occtUnit,
                                                      const std::vector<int>& directoryEntries,
                                                      const std::vector<char>& projectEdges);
StepFile readStepIsolated(const std::string& path);
/// Writes the patches as B-spline faces (trimmed ones bounded by their loops; model-space edge
/// curves computed by OpenCASCADE) in a STEP file of `schema` ("AP214" or "AP242"), length unit
/// set.unit (mm when empty), reals with 17 significant digits. Throws InputError if the file
/// cannot be written, GeometryError naming the patch OpenCASCADE refuses.
void writeStep(const geometry::PatchSet& set, const std::string& path, const std::string& schema);

}  // namespace aero::cad::occt
