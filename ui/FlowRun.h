#pragma once
// A flow solve's work, as it runs on the worker thread (no Qt, no VTK, no Document): the case's
// shape, mesh and flow stages through study::CaseEvaluator, the same call `aeroform-cli flow`
// makes, on a copy of the document's case; then the nodal fields the window shows (entropy, Cp,
// Mach, pressure: libcore/flow/Outputs.h) and, for a run that stopped early, the restart file the
// CLI would keep. The GUI thread fills a FlowRunInput, runs runFlowSolve() as a job of the
// JobRunner and hands the result (shared, read-only from then on) to the scene and panels.
// Also here: the displayed fields by name, unit and colour scale.
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flow/FlowSolver.h"
#include "geometry/PatchSet.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"

namespace aero::ui {

// ---- Fields ---------------------------------------------------------------------------------------

enum class FlowField { Entropy = 0, PressureCoefficient, Mach, Pressure };
inline constexpr int kFlowFields = 4;

/// "Entropy s - s\u221e", "Pressure coefficient Cp", ... (for people, with the symbol).
const char* flowFieldLabel(FlowField f);
/// "entropy", "cp", "mach", "pressure" (settings keys and exported column names).
const char* flowFieldKey(FlowField f);
/// "p / (rho_inf a_inf^2)", ... ("" when dimensionless).
const char* flowFieldUnit(FlowField f);
/// The colour of position t in [0, 1] on the field colour scale (blue, cyan, green, yellow, red:
/// the contour plots of the paper's Figure 6). RGB in [0, 1].
std::array<double, 3> fieldColour(double t);

// ---- The work -------------------------------------------------------------------------------------

struct FlowRunInput {
    geometry::PatchSet baseline;  // the case's geometry, loaded by the document
    io::CaseFile caseFile;        // the document's case (flow.present is forced on)
    std::vector<double> wall;     // the document's wall when the run started (unique control
                                  // points, 3 each): what the result is compared with later
    std::string restartFrom;      // non-empty: continue from this restart file (same grid)
    std::string warmStateFrom;    // non-empty: start from this bare state (io::readWarmState: an
                                  // optimization's stored evaluation) when it fits the grid;
                                  // a missing, damaged or other-grid file is the usual start
    std::string restartTo;        // non-empty: where a run that stops early keeps its state
    bool restartAlways = false;   // ... and a converged one too (the case's output.restart);
                                  // otherwise a converged run removes a stale file there
};

/// One report of a running solve (typed progress: JobContext<FlowRunProgress>).
struct FlowRunProgress {
    study::Stage stage = study::Stage::Shape;
    std::string message;           // a line for people (may be empty for iterations)
    double fraction = -1;          // of the stage, when known
    bool hasIteration = false;     // the flow stage's iteration below is set
    flow::FlowIteration iteration; // a copy (rejected attempts included: iteration.rejected)
    bool coarse = false;           // the grid-sequencing pre-solve's
    int iterationOffset = 0;       // iterations of the run a restart continues
};

struct FlowRunResult {
    study::EvaluationStatus status = study::EvaluationStatus::Ok;
    std::string message;                           // why it did not converge / failed / stopped
    std::shared_ptr<const study::FlowResult> flow; // null when the shape or mesh stage failed
    std::array<std::vector<double>, kFlowFields> fields;  // per node (global order), FlowField order
    std::array<std::array<double, 2>, kFlowFields> range{};  // finite min and max of each field
    std::vector<double> wall;                      // the input's wall
    std::string restartWritten;                    // the restart file written, if any
    std::string restartError;                      // why it could not be written
    double seconds = 0;                            // wall-clock time of the whole run

    bool converged() const { return flow && flow->report.converged(); }
    /// Nodes of the flow grid (0 without a solution).
    long nodes() const { return flow ? flow->mesh.nodeCount : 0; }
};

using FlowRunProgressFn = std::function<void(const FlowRunProgress&)>;

/// Runs the pipeline. Never throws for a bad design (the status says why: InvalidShape,
/// InvalidMesh, FlowNotConverged, Cancelled); throws aero::Error for a bad case (like the CLI)
/// or an unreadable restart. A run that did not converge (or was cancelled) in the flow stage
/// keeps its state in in.restartTo, as `aeroform-cli flow` does.
FlowRunResult runFlowSolve(const FlowRunInput& in, const FlowRunProgressFn& progress = {},
                           const std::atomic<bool>* cancel = nullptr);

/// The fields of a solution, in FlowField order (libcore's Cp, Mach and entropy; the pressure
/// p / (rho_inf a_inf^2) of each node).
std::array<std::vector<double>, kFlowFields> flowFields(const study::FlowResult& r);

}  // namespace aero::ui
