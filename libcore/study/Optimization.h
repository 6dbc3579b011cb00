#pragma once
// The design optimization of a case (Sections IV.C and V of the paper): the case's evaluator and
// the adjoint gradient behind an optimizer of libcore/optimize.
//
// Variables: the design variables in the case's units and, optionally, the angle of attack in
// degrees (or each divided by its range: optimization.variable_scaling). Objective: scale * (-J or J) for the
// case's functional J. Constraints: the case's linear ones (symmetry across Y = 0, adjacent-station
// gaps) as linear rows, the enclosed volume >= its bound (V / V_start, exact gradient through both
// FFD levels) and optionally CL = target (the adjoint's dCL/dv).
//
// Every evaluation is appended, as it happens, to the history: `<history>.jsonl` (exact, what
// --resume replays), `<history>.csv` (per evaluation: status, J, CL, CD, volume, flow and adjoint
// iterations, times, the design) and `<history stem>_iterations.csv` (per major iteration:
// objective, optimality, feasibility). Each evaluation's flow starts from the state of the
// design its step came from: of the optimizer's last two iterates, the one closer to it (a line
// search runs from one of them; before the first iterate, from the accepted evaluation closest to
// it: closestWarmStart), not from the last converged evaluation, which may be a rejected
// line-search trial on another branch of the flow. The states are kept
// on disk (the newest few accepted ones and the optimizer's last two iterates) so that a resumed
// run starts its next evaluation from the same state: a run killed at any moment and resumed
// reaches the same iterates, bit for bit, without solving again what the history holds.
#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "geometry/Planform.h"
#include "optimize/Optimizer.h"
#include "study/CaseEvaluator.h"

namespace aero::study {

/// One line of the history (JSON lines).
struct OptimizationRecord {
    enum class Kind { Header, Values, Gradient, Iteration };
    Kind kind = Kind::Values;
    int index = 0;                  // values: evaluation number; gradient: gradient number;
                                    // iteration: iteration number (all from 1; iteration 0 = start)
    std::vector<double> x;          // the optimizer's (scaled) variables
    bool ok = true;
    std::string status;             // an EvaluationStatus name, or "ok"
    std::string message;            // why it failed
    double objective = 0;           // what the optimizer minimizes
    std::vector<double> constraints;  // the nonlinear constraints (volume ratio, CL)
    // Values: the evaluation.
    double J = 0, CL = 0, CD = 0, CM = 0, volume = 0, alphaDeg = 0;
    geometry::Planform planform;    // of the evaluated shape (all 0: not computed)
    double cornerRatio = 0;         // log of the grid's smallest corner ratio (smooth; 0: not computed)
    double wallBend = 0;            // the wall's sharpest node-to-node bend, degrees (0: no grid)
    double growingMode = std::numeric_limits<double>::quiet_NaN();  // a flow that did not converge
                                    // (flow.stall_modes): the fastest growing mode's rate, 0 when
                                    // none grows; NaN when not looked for
    double maxMach = 0, maxEntropy = 0;  // the flow's largest local Mach number and |s - s_inf|: a
                                         // check that the optimizer's designs stay physical
    int flowIterations = 0;
    int warmFrom = 0;               // the evaluation whose state this flow started from (0: cold)
    double seconds = 0;
    // Gradient.
    std::vector<double> dObjective;
    std::vector<std::vector<double>> dConstraints;
    int adjointIterations = 0;      // GMRES iterations of all flow adjoints
    // Iteration.
    int evaluations = 0, gradients = 0;
    double optimality = 0, feasibility = 0;
    // Header: what the history belongs to (checked on resume).
    std::vector<std::string> names;  // the optimizer's variables
    std::vector<std::string> constraintNames;  // its nonlinear constraints
    std::string optimizer, objectiveName;
    bool replayed = false;           // read back on --resume, not run again
};
const char* recordKindName(OptimizationRecord::Kind k);
/// The design an optimization of case c starts from: the case's own (`own`, model order), or the
/// design values (and flow.alpha, when alpha is a variable) of the case optimization.start_design
/// names, by variable name (the ones it does not give at their baselines). Throws
/// CaseError naming that key and the start case's variable or value that does not fit c (an
/// unknown name, a value outside the bounds, a file that cannot be read).
struct StartDesign {
    std::vector<double> values;
    double alphaDeg = 0;
    int changed = 0;  // design variables that differ from `own`
};
StartDesign startDesign(const io::CaseFile& c, const ffd::FfdModel& model, const std::vector<double>& own);

/// A values record whose flow converged: accepted, or refused by optimization.max_entropy or
/// max_entropy_rise (status "flow-unresolved"). Its forces, max Mach and entropy mean something;
/// its objective only if it is ok.
bool hasConvergedFlow(const OptimizationRecord& r);

struct OptimizationOptions {
    bool resume = false;     // continue the history (replayed, then run on); false: a new run,
                             // refused if a history exists unless `fresh`
    bool fresh = false;      // replace an existing history
    const std::atomic<bool>* cancel = nullptr;
    Log log;                 // lines for a human
    std::function<void(const OptimizationRecord&)> onRecord;  // every record written or replayed
    // Every evaluation run here (not replayed, not cancelled), with its record, just before the
    // record is written: the shape, grid and flow themselves (e.g. for a viewer; read only, on
    // the optimizer's thread).
    std::function<void(const OptimizationRecord&, const Evaluation&)> onEvaluation;
    ProgressFn progress;     // the evaluations' stages and flow iterations
};

struct OptimizationSummary {
    optimize::Result result;
    std::vector<std::string> names;      // the optimizer's variables
    std::vector<double> values;          // the best design (design variables)
    double alphaDeg = 0;
    flow::ForceCoefficients forces;      // at the best design
    int bestEvaluation = 0;              // the history's number of the best design's evaluation
                                         // (0: not in the history, e.g. a failed start)
    double J = 0, volume = 0;
    /// The accepted evaluation of least objective among those that miss the feasibility tolerance
    /// by at most 1e-3 (largest violation of a bound, row or constraint: the constraints are
    /// ratios, Mach numbers, degrees), when it is better than the best design; 0: none. A run
    /// stopped early along a constraint's boundary, as SLSQP's iterates are (feasible only as
    /// they converge), has such designs; `--design N` writes one as a case.
    int nearlyFeasibleEvaluation = 0;
    double nearlyFeasibleObjective = 0, nearlyFeasibleJ = 0, nearlyFeasibleInfeasibility = 0;
    double startVolume = 0;              // of the case's own design: the volume constraint's
                                         // reference (the optimizer's start too, unless
                                         // optimization.start_design names another)
    geometry::Planform planform, startPlanform;  // of the best and the optimizer's starting shape
    int replayedEvaluations = 0, replayedGradients = 0;
    int coldFlowIterations = 0;          // the first evaluation's flow iterations (cold start)
    int warmStarts = 0;                  // evaluations warm-started ...
    double meanWarmFlowIterations = 0;   // ... and their mean flow iterations
    std::string historyCsv, historyJsonl, iterationsCsv, finalGeometry;
    double seconds = 0;
};

/// A converged flow an evaluation may start from: an accepted evaluation and its point in the
/// optimizer's variables.
struct WarmCandidate {
    int evaluation = 0;
    std::vector<double> x;
};
/// The evaluation of the candidate closest to x (Euclidean distance in the optimizer's
/// variables); of equally close ones (within a relative 1e-6) the older: a line-search trial
/// halfway between the design its step came from and a rejected full step starts from the
/// former. 0 when there is no candidate.
int closestWarmStart(const std::vector<WarmCandidate>& candidates, const std::vector<double>& x);

/// Of the accepted evaluations in `values` that miss the feasibility `tolerance` by at most 1e-3
/// (optimize::feasibility: the largest violation of a bound, row or constraint) and have an
/// objective below `bestObjective`, the one of least objective: its evaluation number (0: none)
/// and its violation. OptimizationSummary::nearlyFeasibleEvaluation.
std::pair<int, double> nearlyFeasibleBest(const optimize::Problem& p, const std::vector<OptimizationRecord>& values,
                                          double bestObjective, double tolerance);

/// Runs the case's optimization section. Throws CaseError for a case without one (or without
/// design variables), InputError for a history that cannot be read or written or belongs to
/// another problem. Failed evaluations are not errors: the optimizer cuts its step.
OptimizationSummary optimizeCase(CaseEvaluator& ev, const OptimizationOptions& o = {});

/// Evaluation `evaluation` (1-based, as the history numbers it) of the case's optimization
/// history as a case of its own (CaseEvaluator::designCase: its design values and angle of
/// attack, its objective or failure in the description), for `aeroform-cli flow` to solve or
/// analyse again (`aeroform-cli optimize --design`). Throws InputError for a missing or unreadable
/// history or one of another problem, CaseError when it has no such evaluation (naming how many
/// it has).
io::CaseFile evaluationCase(const CaseEvaluator& ev, int evaluation);

/// The JSON-lines history beside a CSV history path (".csv" -> ".jsonl").
std::string historyJsonlPath(const std::string& csv);

/// Where an optimization keeps the converged flow state of an evaluation for its warm starts:
/// `<history stem>.states/<evaluation>.state` beside the CSV history (io::readWarmState reads it;
/// only the newest few accepted evaluations and the optimizer's last two iterates are kept).
std::string warmStatePath(const std::string& csv, int evaluation);

/// The records of a JSON-lines history, in order. A last line that is incomplete (a run killed
/// while writing it) is dropped; any other bad line throws InputError naming the file and line.
std::vector<OptimizationRecord> readHistory(const std::string& jsonl);

}  // namespace aero::study
