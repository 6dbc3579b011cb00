#pragma once
// Case files (`aeroform.case`, version 1; schema in docs/case-file.md): geometry, FFD lattices,
// design variables and their values, lattice displacements, embedding options, constraints and
// outputs. Reading validates every key and names it in errors (CaseError); building turns a case
// and its loaded geometry into an FfdModel.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ffd/FfdModel.h"
#include "flow/FlowSolver.h"
#include "flow/Outputs.h"
#include "mesh/Elasticity.h"
#include "mesh/Extrusion.h"

namespace aero::io {

struct LatticeCase {
    std::string name;
    std::array<int, 3> counts{6, 6, 2};
    std::array<int, 3> degrees{3, 3, 1};
    std::array<double, 3> padding{0.05, 0.05, 0.05};
    std::array<std::array<double, 3>, 3> axes{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    std::optional<ffd::LatticeBox> box;       // explicit box (overrides padding)
    std::vector<int> patches;                 // owned patches (0-based; all if empty)
    std::vector<std::pair<int, std::vector<double>>> refine;  // (direction, knots)
    std::vector<std::pair<int, double>> crease;               // (direction, parameter)
};

struct PointVariableCase {
    int lattice = 0;
    std::array<int, 3> index{0, 0, 0};
    std::string axes = "xyz";
    std::array<double, 2> bounds{-0.5, 0.5};
};

struct DisplacementCase {
    int lattice = 0;
    std::array<int, 3> index{0, 0, 0};
    std::array<double, 3> delta{0, 0, 0};
};

/// The second FFD level: mesh generation (a named level plus overrides) and movement options.
struct MeshCase {
    bool present = false;  // the case has a "mesh" section
    std::string level = "coarse";
    mesh::ExtrusionOptions extrusion = mesh::extrusionLevel("coarse");
    mesh::ElasticityOptions elasticity;
};

/// The flow solution (case key "flow"): free stream, force reference, dissipation and solver
/// options. A case with a flow section is meshed with the "mesh" section (or its defaults).
struct FlowCase {
    bool present = false;
    flow::FreeStream freeStream;
    flow::ForceReference reference{3.14159265358979323846 / 2, 1.0, {0, 0, 0}};  // area pi/2: the
                                      // half-sphere's half frontal disc (one default, here)
    flow::DissipationOptions dissipation;
    flow::InviscidScheme scheme = flow::InviscidScheme::EntropyConservative;
    flow::NewtonOptions newton;
    std::string restart;              // start from this restart file (resolved), empty: free stream
    bool gridSequencing = true;       // a cold start on a grid of sequencingNodes nodes or more
                                      // first solves on coarser samplings of the same analytic
                                      // grid (half the intervals, a quarter, ...)
    int sequencingNodes = 40000;      // ... from this many grid nodes on; a coarser level is
                                      // added while the coarsest has this many (docs/validation.md)
    bool stallModes = true;           // a solve that does not converge looks for the linear modes
                                      // that grow in pseudo time at its final state (the reason)
    double maxSeconds = 0;            // > 0: the flow stage's wall-time budget, all its solves
                                      // together (flow.max_seconds; CaseEvaluator)
    double checkpointSeconds = 60;    // `aeroform-cli flow` writes its restart file at most this
                                      // often during the solve (0: every iteration)
};

/// The design optimization (case key "optimization", Section IV.C of the paper): the objective, the
/// optimizer and its limits; the constraints are the case's "constraints" (symmetry, station
/// gaps, minimum volume) plus an optional lift target. Options in io::optimizationOptions().
struct OptimizationCase {
    bool present = false;
    std::string objective = "CL/CD";   // a functional of the adjoint layer: CL, CD, CM, CY, CL/CD,
                                       // pressure (the inverse design's mismatch to targetPressure)
    std::string targetPressure;        // wall pressures (io::writeWallPressureCsv), resolved
    bool maximize = true;              // "sense": maximize or minimize
    double objectiveScale = 1;         // the optimizer sees scale * (+-J)
    bool rangeScaling = false;         // "variable_scaling": "range" divides each variable by its
                                       // range; "none" (default) keeps the case's units
    std::string optimizer = "ipopt";   // optimize::optimizerNames()
    double optimalityTolerance = 1e-6;
    double feasibilityTolerance = 1e-6;
    int maxIterations = 50;
    int maxEvaluations = 100;
    bool alphaVariable = false;        // the angle of attack is a variable too (flow.alpha its start)
    double alphaLower = -5, alphaUpper = 10;  // degrees
    double minCornerRatio = 0.01;      // every grid cell corner keeps this fraction of its baseline
                                       // volume (0: no grid-validity constraint)
    double maxWallBend = 0;            // degrees the wall may turn from grid node to node (0: free)
    double maxWallMach = 0;            // the wall's local Mach number (a smooth maximum) stays below
                                       // this (0: free)
    double maxEntropy = 0;             // a converged flow with a larger |s - s_inf| is a failed
                                       // evaluation (0: any)
    double maxEntropyRise = 0;         // ... and one whose |s - s_inf| is more than this many times
                                       // the design's it started from (0: any)
    std::string warmStartFallback = "continuation";  // after a warm start stalls: "continuation"
                                       // (free stream, then the dissipation continuation),
                                       // "free_stream", or "none" (a failed evaluation at once)
    int warmStartIterations = 80;      // a step's warm start that has not converged after this many
                                       // flow iterations fails like a stall (0: flow.max_iterations)
    bool stallModes = false;           // a step from an accepted design whose flow does not converge
                                       // runs the mode analysis (flow.stall_modes) too; the first
                                       // evaluation follows flow.stall_modes
    bool liftConstraint = false;       // CL = targetCL (e.g. minimum drag at a fixed lift)
    double targetCL = 0;
    std::string history;               // evaluation history (.csv; the .jsonl beside it is what
                                       // --resume replays); resolved; default beside the case
    std::string iterations;            // folder for each major iteration's shape (IGES, VTK);
                                       // resolved; empty: none
    std::string startDesign;           // a case whose design values (and flow.alpha, when alpha is
                                       // a variable) the optimizer starts from, e.g. the best design
                                       // of a run on a coarser grid; the problem stays this case's
                                       // (min_volume "initial" is this case's own design's volume);
                                       // resolved; empty: this case's own values
};

/// Minimum thickness (case key "constraints.thickness"): measured along z at every station y times
/// chord fraction of that station's section, and at explicit (x, y) points; each point keeps at
/// least `minRatio` of its baseline thickness (ffd::ThicknessConstraints).
struct ThicknessCase {
    std::vector<double> stations;
    std::vector<double> chordFractions;
    std::vector<std::array<double, 2>> points;
    double minRatio = 1;
    bool present() const { return !points.empty() || !stations.empty(); }
};

struct CaseFile {
    std::string path;       // the case file itself
    std::string description;  // free text, kept when the GUI saves the case
    std::string geometry;   // resolved against the case file's folder
    std::vector<LatticeCase> lattices;
    std::vector<ffd::StationSpec> stations;
    std::vector<PointVariableCase> pointVariables;
    std::map<std::string, double> values;      // design-variable values by name
    std::vector<DisplacementCase> displacements;
    ffd::EmbeddingOptions embedding;
    bool allowOutside = false;
    bool symmetry = true;                      // report/enforce symmetry across Y = 0
    std::optional<double> stationGap;          // minimum gap between adjacent stations
    std::optional<double> stationSecondDifference;  // bound on |d(s-1) - 2 d(s) + d(s+1)| of
                                                    // each lattice point's displacement
    std::optional<double> minVolume;           // absolute; NaN means "initial volume"
    ThicknessCase thickness;                   // minimum thickness at planform points
    double minLatticeJacobian = 0;             // smooth bound of det J / det J baseline over the
                                               // lattices (ffd/ShapeConstraints.h); 0: none
    std::string outputGeometry;                // deformed IGES/JSON (resolved), empty: none
    std::string outputVtk;                     // deformed VTK multiblock (.vtm), empty: none
    MeshCase mesh;
    std::string outputMeshVtk;                 // grid with quality fields (.vtm)
    std::string outputControlVtk;              // control grid b (.vtm)
    std::string outputPlot3d;                  // grid as multiblock Plot3D (binary .xyz / ASCII .p3d)
    FlowCase flow;
    std::string outputFlowVtk;                 // flow solution fields + wall Cp (.vtm)
    std::string outputResidualCsv;             // residual history (.csv)
    std::string outputRestart;                 // restart file written at the end (.restart)
    std::string outputWallPressure;            // pressure per wall node (.csv): an inverse design's target
    OptimizationCase optimization;
};

/// Reads and validates a case file; throws InputError (file) or CaseError naming the key.
CaseFile readCase(const std::string& path);
CaseFile parseCase(const std::string& text, const std::string& path);

/// True if the file's top-level "format" is "aeroform.case" (cheap sniffing for --batch).
bool looksLikeCase(const std::string& path);

/// Lattices of the case around `geometry`, and the model with its design variables.
/// Throws CaseError for references to unknown patches or lattices (naming the key).
ffd::FfdModel buildModel(const CaseFile& c, const geometry::PatchSet& geometry);

/// Control points per direction of a case lattice after its refinements and creases: what the
/// indices of displacements and point variables refer to.
std::array<int, 3> refinedCounts(const LatticeCase& lc);

/// Why `path` cannot be an optimization.start_design (not a case file, .json), or "" if it can.
std::string startDesignPathProblem(const std::string& path);

/// Design-variable values of the case (baseline where not given). Throws CaseError naming an
/// unknown variable or a value outside its bounds.
std::vector<double> designValues(const CaseFile& c, const ffd::FfdModel& model);

/// The moved lattices: B(v) plus the case's explicit displacements.
std::vector<ffd::Lattice> movedLattices(const CaseFile& c, const ffd::FfdModel& model, const std::vector<double>& v);

}  // namespace aero::io
