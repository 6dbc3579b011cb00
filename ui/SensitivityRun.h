#pragma once
// Flow > Compute Sensitivities, the worker's side (no Qt, no VTK, no Document): the current
// design's shape, mesh and flow stages through study::CaseEvaluator (as a flow solve) and then
// study::computeGradient of one objective with its geometry outputs: dJ/dv per design variable,
// dJ/dB per lattice control point and dJ/dA per geometry control point. The GUI thread fills a
// SensitivityInput, runs runSensitivities() as a job of the JobRunner and keeps the result
// (shared, read-only) for the design variable bars, the lattice arrows and the first-order
// prediction of a drag (predictedChange).
#include <array>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ffd/Lattice.h"
#include "flow/Outputs.h"
#include "geometry/PatchSet.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"

namespace aero::ui {

/// The objective a designer improves: the case's optimization objective and sense when it has
/// an optimization section, else CL/CD maximized.
struct Objective {
    std::string name = "CL/CD";
    bool maximize = true;
};
Objective caseObjective(const io::CaseFile& c);
/// The objective's value from force coefficients ("CL", "CD", "CM", "CY", "CL/CD"); nullopt for
/// one that is not a force (the inverse design's pressure mismatch).
std::optional<double> objectiveValue(const std::string& name, const flow::ForceCoefficients& forces);

struct SensitivityInput {
    geometry::PatchSet baseline;  // the case's geometry, loaded by the document
    io::CaseFile caseFile;        // the document's case (flow.present is forced on)
    Objective objective;
    std::vector<double> warmState;  // non-empty: the flow starts here (a converged solution of
                                    // this design and grid, e.g. the last Flow > Solve)
};

struct SensitivityResult {
    bool ok = false;
    std::string message;                    // why not ok (the flow did not converge, ...)
    Objective objective;
    double J = 0;                           // its value at the design
    flow::ForceCoefficients forces;
    std::vector<double> values;             // the design evaluated (model order)
    std::vector<ffd::Lattice> lattices;     // its moved lattices B (displacements included)
    std::vector<double> dv;                 // dJ/dv, per design variable
    std::vector<std::vector<double>> dLattice;  // dJ/dB per lattice, 3 per lattice point
    std::vector<double> dUnique;            // dJ/dA, 3 per unique geometry control point
    int flowIterations = 0;
    double secondsFlow = 0, secondsGradient = 0;
};

/// One line for the status bar: what the job is doing.
using SensitivityStatusFn = std::function<void(double fraction, const std::string& line)>;

/// Evaluates the design and differentiates the objective. Never throws for a bad design or a
/// solve that does not converge (the result says why); throws aero::Error for a bad case.
SensitivityResult runSensitivities(const SensitivityInput& in, const SensitivityStatusFn& status = {},
                                   const std::atomic<bool>* cancel = nullptr);

/// First order change of J when the lattices move from r.lattices to `now` (the same lattices,
/// e.g. a drag's preview or after a slider move): sum over lattice points of dJ/dB . (B - B0).
/// nullopt when the lattices do not match (another structure).
std::optional<double> predictedChange(const SensitivityResult& r, const std::vector<ffd::Lattice>& now);

// ---- The surface sensitivity --------------------------------------------------------------------

/// The normal component of the control points' sensitivity on one drawn patch: dJ/dA
/// interpolated at the parameters `uv` (2 per point) with the patch's own rational basis,
/// g(u, v) = sum_i R_i(u, v) dJ/dA_i, dotted with the unit `normals` (3 per point). `gradientNet`:
/// the patch with dJ/dA as control points (ffd::scatter of SensitivityResult::dUnique into the
/// baseline). Not a derivative per unit area: each control point's share of the wall.
std::vector<double> normalSensitivity(const geometry::Patch& gradientNet, const std::vector<double>& uv,
                                      const std::vector<double>& normals);

/// Unit vertex normals of a triangulated patch (points 3 each, triangles 3 indices each), area
/// weighted, turned to point away from `centre` on the whole (one sign per patch).
std::vector<double> outwardNormals(const std::vector<double>& points, const std::vector<int>& triangles,
                                   const std::array<double, 3>& centre);

}  // namespace aero::ui
