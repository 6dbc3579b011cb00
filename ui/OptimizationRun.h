#pragma once
// An optimization's work as it runs on the worker thread (no Qt, no VTK, no Document): the case's
// optimization section through study::optimizeCase, the same call `aeroform-cli optimize` makes,
// on a copy of the document's case. What comes out, as typed progress for the GUI thread:
//   records      every history record as it is written or replayed (values, gradient, iteration);
//   snapshots    with each values record the evaluation itself: its design, shape, moved
//                lattices and (when it got that far) its flow solution with the fields the 3D
//                view colours (FlowRun.h), so the view follows the run and the history slider
//                can bring any evaluation back; a replayed evaluation (resume) gets its shape
//                stage again, exactly (same design, same arithmetic), but no flow;
//   flow         the current flow solve's stages and iterations (the residual plot);
//   log          the optimizer's lines for people.
// Pausing: when `pause` is set the run stops at the next record boundary (after an evaluation or
// a gradient is written): the history then ends on a whole record and `resume` continues it by
// replaying it (study/Optimization.h: bit for bit the path an uninterrupted run takes). A stop
// (the job's cancel flag) ends within a flow iteration; the evaluation it interrupted is not
// recorded and is solved again on resume.
// Also here: reading an existing history back (after the application was closed or crashed),
// with every evaluation's shape, for the plots and the history slider.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "FlowRun.h"
#include "ffd/Injectivity.h"
#include "ffd/Lattice.h"
#include "geometry/PatchSet.h"
#include "io/CaseFile.h"
#include "study/Optimization.h"

namespace aero::ui {

/// One evaluation as the window shows it (shared, read-only once made).
struct EvaluationSnapshot {
    int index = 0;                       // evaluation number, from 1
    std::vector<double> values;          // its design: the design variables in model order
    double alphaDeg = 0;                 // its angle of attack
    geometry::PatchSet shape;            // the deformed geometry
    std::vector<ffd::Lattice> lattices;  // the moved lattices
    std::vector<ffd::InjectivityReport> injectivity;  // one per lattice
    std::shared_ptr<const FlowRunResult> flow;        // its solution and fields; null when not
                                                // kept (replayed, read back, or no flow stage)
};

/// One report of a running optimization (typed progress: JobContext<OptimizationProgress>).
struct OptimizationProgress {
    enum class Kind { Record, Flow, Log };
    Kind kind = Kind::Log;
    study::OptimizationRecord record;                    // Record
    std::shared_ptr<const EvaluationSnapshot> snapshot;  // Record of kind Values: the evaluation
    FlowRunProgress flow;                                // Flow: a stage line or a flow iteration
    std::string line;                                    // Log
};

struct OptimizationRunInput {
    geometry::PatchSet baseline;  // the case's geometry, loaded by the document
    io::CaseFile caseFile;        // the document's case (optimization.history resolved)
    bool resume = false;          // continue the history (replayed, then run on)
    bool fresh = false;           // replace an existing history
    bool keepFlow = true;         // send each evaluation's solution with its snapshot
    std::shared_ptr<std::atomic<bool>> pause;  // set by the GUI: stop at the next record boundary
};

struct OptimizationRunResult {
    std::optional<study::OptimizationSummary>
        summary;          // how the optimizer ended (also when stopped)
    bool paused = false;  // it stopped because `pause` was set, at a record boundary
    int lastRecordedEvaluation = 0;
};

using OptimizationProgressFn = std::function<void(OptimizationProgress)>;

/// Runs the case's optimization. `cancel` is polled by libcore between flow iterations;
/// `requestCancel` sets it (the pause uses it at a record boundary). Throws aero::Error for a bad
/// case or a history that cannot be resumed (as the CLI reports them).
OptimizationRunResult runOptimization(const OptimizationRunInput& in,
                                      const OptimizationProgressFn& report,
                                      const std::atomic<bool>* cancel,
                                      const std::function<void()>& requestCancel);

/// What an existing history holds, read back with every evaluation's shape.
struct LoadedHistory {
    std::vector<study::OptimizationRecord> records;  // in the file's order, the header first
    std::vector<std::shared_ptr<const EvaluationSnapshot>> snapshots;  // one per values record
};

/// Reads the history of the case (optimization.history's JSON lines) and evaluates the shape
/// stage of every recorded evaluation. Throws aero::Error when it cannot be read.
LoadedHistory loadOptimizationHistory(const geometry::PatchSet& baseline, const io::CaseFile& c,
                                      const std::atomic<bool>* cancel = nullptr);

/// The design (design variables in model order) and angle of attack of the optimizer's variables
/// x, as study::optimizeCase maps them (each variable times its range with variable_scaling
/// "range"; alpha last when it is a variable).
struct DesignPoint {
    std::vector<double> values;
    double alphaDeg = 0;
};
DesignPoint designPoint(const io::CaseFile& c, const std::vector<ffd::DesignVariable>& variables,
                        const std::vector<double>& x);

/// A solution as the window keeps it: the evaluation's flow without what only the solver needs
/// (the metrics), with the nodal fields and their ranges.
std::shared_ptr<const FlowRunResult> keptSolution(const study::Evaluation& e);

}  // namespace aero::ui
