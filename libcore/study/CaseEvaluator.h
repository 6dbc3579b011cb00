#pragma once
// One case evaluated at any design: the function evaluation that the CLI (deform, mesh, flow,
// sweep, --batch), the GUI and the optimizer call (docs/architecture.md, "One pipeline").
//
// Built once from a case and its loaded geometry: the FFD model (lattices embedded once), the
// case's design values, and (on first use) the baseline control grid extruded around the
// baseline geometry. evaluate(v) then runs the stages
//   shape: B(v) + displacements -> injectivity -> deformed geometry A(v)
//   mesh:  the baseline control grid moved by elasticity to A(v) -> grid x = N b -> quality
//   flow:  metrics -> Euler solution (warm-started from the last converged state on the same grid,
//          or grid-sequenced from a coarser sampling of the same analytic grid) -> forces
// with progress and cancellation at every stage. A design nobody has looked at may fail: the
// result is a status with the reason in terms a user can act on (which lattice, block, node or
// quantity), never an exception (exceptions are for a bad case, at construction).
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adjoint/FlowModes.h"
#include "ffd/Injectivity.h"
#include "flow/FlowMesh.h"
#include "flow/FlowSolver.h"
#include "flow/Outputs.h"
#include "flow/TimeAccurate.h"
#include "io/CaseFile.h"
#include "mesh/Elasticity.h"
#include "mesh/Quality.h"

namespace aero::io {
struct RestartInfo;
}  // namespace aero::io

namespace aero::study {

/// Progress lines for a human ("embedded 521 of 521 ..."); may be empty.
using Log = std::function<void(const std::string&)>;

enum class Stage { Shape, Mesh, Flow };
const char* stageName(Stage s);

/// What a running evaluation reports: the stage, a line for a human, and the flow iteration
/// (non-null during the flow stage, after every iteration or rejected attempt).
struct Progress {
    Stage stage = Stage::Shape;
    std::string message;
    const flow::FlowIteration* iteration = nullptr;
    bool coarse = false;  // the iteration belongs to a grid-sequencing pre-solve on a coarser grid
    int iterationOffset = 0;  // iterations done before this run (a continued restart; for a
                              // pre-solve, those of the coarser levels before it)
    double fraction = -1;     // how much of the stage is done, in [0, 1] (-1: unknown)
    const flow::TimeStepRecord* timeStep = nullptr;  // a time-accurate run's step just taken ...
    const flow::ForceCoefficients* forces = nullptr; // ... and the forces after it
};
using ProgressFn = std::function<void(const Progress&)>;

enum class EvaluationStatus {
    Ok,
    InvalidShape,      // a moved lattice is not injective (the geometry could self-intersect)
    InvalidMesh,       // the moved grid has a folded cell, or the mesh movement did not converge
    FlowNotConverged,  // the flow solver stopped without converging (reason in the message)
    Cancelled,
};
const char* evaluationStatusName(EvaluationStatus s);

/// Where a flow starts: the free stream, the evaluator's last converged state (warm start), a
/// given state (a restart), or a solve on a coarser sampling of the same grid (sequencing).
struct FlowStart {
    std::string restartFile;          // non-empty: read the state from this restart file (same
                                      // grid; with the same free stream the run is continued:
                                      // its iteration count, reference residual, CFL, lumping;
                                      // of another sampling of the same analytic grid, with the
                                      // grid parameters recorded: interpolated, a start only)
    std::vector<double> state;        // non-empty: start here (5 per node of this grid)
    double referenceResidual = 0;     // > 0: the run this one continues (restart)
    double cflBase = 0;               // > 0: the CFL law's base to continue with
    double lumping = 0;               // > 0: the preconditioner's lumping to continue with
};

/// The continuation in the dissipation that a failed cold solve is given
/// (EvaluationRequest::dissipationRetry): solves with the case's kappa2 and kappa4 times a factor,
/// stage by stage (DissipationContinuation), the first from the free stream at 4 times. A factor
/// of 1 is an attempt at the case's own problem: when it converges, that is the answer and the
/// continuation ends. Each stage starts from the state the stages before handed on: a stage
/// above 1 hands on its state when it converged, or when it stalled or ran out of iterations after
/// an earlier one converged and ended below the residual it started at (a stall that close to the
/// answer is a start as good as a converged state; one that climbed has left it, and the state
/// before stays); a failed attempt at the case's own problem, a diverged or a non-physical stage
/// hands on nothing.
///
/// The factors the continuation goes down through, from the largest: 16 and 8 are climbed to
/// (from the free stream) only while no stage has converged, 4 is the first stage.
inline constexpr std::array<double, 6> kDissipationLadder = {16.0, 8.0, 4.0, 2.0, 1.4142135623730951, 1.0};
inline constexpr double kDissipationFirst = 4.0;
/// The smallest ratio between the factor a stage starts from and its own: a stage that does not
/// hand on is retried halfway (in the exponent) between the two, then the factor it missed
/// again, down to this ratio (2^(1/16)). The steps below 2^(1/2) of the earlier fixed schedule
/// (2^(1/4), 2^(1/8)) are such halvings: the 98k random design 3 of the robustness study needs
/// them (docs/validation.md).
inline constexpr double kDissipationFinestRatio = 1.0442737824274138;
/// At most this many stages (each 1-10 minutes on the 98k optimization grid; flow.max_seconds
/// bounds the time too).
inline constexpr int kDissipationMaxStages = 16;

/// The order of the continuation's stages, from the outcome of each. Until a stage hands its state
/// on, the continuation climbs from kDissipationFirst (4, 8, 16 times the case's dissipation,
/// each from the free stream: the 98k random designs 5 and 7 stall at 4 and converge at 16 and 8);
/// after that it descends through kDissipationLadder from the factor whose state it holds, and a
/// stage that does not hand on is followed by one halfway (geometrically) between the two, the
/// factor it missed being retried from there (a stack of targets), down to
/// kDissipationFinestRatio. So 4, 2, 1.41 and 1 when every stage converges, and 1.19 then 1 again
/// and 1.09 then 1 again when the case's own problem does not converge from 1.41 and 1.19.
class DissipationContinuation {
public:
    /// The factor of the next stage (times the case's kappa2 and kappa4; 1: the case's own
    /// problem); 0 when the continuation is over.
    double next() const { return next_; }
    /// The factor whose state the next stage starts from; 0: none has been handed on (the stage
    /// starts from the free stream).
    double from() const { return from_; }
    int stages() const { return stages_; }
    /// How the stage at next() ended: whether its state was handed on (continuationHandsOn). An
    /// attempt at the case's own problem that converged ends the continuation either way.
    void ended(bool handedOn);

private:
    double next_ = kDissipationFirst;
    double from_ = 0;
    std::vector<double> targets_;  // factors a stage missed, to be retried; the nearest last
    int stages_ = 0;
};

struct EvaluationRequest {
    bool mesh = true;        // run the mesh stage (the flow stage needs it)
    bool flow = true;        // run the flow stage (if the case has a flow section)
    bool warmStart = true;   // start from the last converged flow on the same grid
    bool coldRetry = true;   // a warm (or grid-sequenced) start that stalls, diverges or is not
                             // physical is solved again from the free stream (a large design step
                             // can leave the neighbour's state in the basin of another,
                             // unconverged branch)
    bool dissipationRetry = true;  // a solve from the free stream that stalls, diverges or is not
                                   // physical is solved again by continuation in the dissipation
                                   // (DissipationContinuation), ending with the case's own problem
    std::optional<bool> sequencing;  // without a warm start: first solve on coarser samplings of
                                     // the grid (unset: the case's flow.grid_sequencing; either way
                                     // only from flow.sequencing_nodes nodes on)
    std::optional<int> warmIterations;  // a warm start stops after this many iterations (then
                                        // the retries follow as after a stall; unset:
                                        // flow.max_iterations)
    std::optional<bool> stallModes;  // a solve that does not converge looks for its growing modes
                                     // (unset: the case's flow.stall_modes)
    std::optional<FlowStart> start;  // overrides the warm start (e.g. a restart file)
    std::optional<flow::TimeAccurateOptions> timeAccurate;  // set: the flow stage runs forward in
                                     // physical time from its start (dual time stepping,
                                     // flow/TimeAccurate.h) instead of solving for a steady state;
                                     // no grid sequencing, retries or continuation (FlowResult::
                                     // timeAccurate, timeForces, timeVerdict)
    std::optional<double> alphaDeg;  // the angle of attack (unset: the case's flow.alpha)
    std::string checkpointFile;      // non-empty: during the flow solve (the full grid's), the state
                                     // is written to this restart file (io::writeRestart, atomic)
    double checkpointSeconds = 60;   // ... at most this often (0: after every iteration), so a
                                     // killed run loses at most this much work
    int worstCells = 10;     // how many of the worst cells the mesh quality summary locates
    // For an editor showing the shape as it is edited (the GUI document):
    bool keepInvalidShape = false;  // fill shape and uniqueSurface also for a non-injective
                                    // lattice (the status still says InvalidShape; the mesh and
                                    // flow stages do not run)
    std::optional<std::vector<io::DisplacementCase>> displacements;  // lattice point
                                    // displacements instead of the case's (e.g. a drag's preview)
};

struct MeshResult {
    mesh::MultiBlockMesh control;            // the moved control grid (the last increment's when
                                             // the move failed: kept for inspection)
    std::vector<mesh::StructuredGrid> grids; // x = N b, one per block (also of a failed move or a
                                             // folded grid, for inspection; empty if cancelled)
    std::vector<mesh::CellQuality> cellQuality;  // per block, per cell
    mesh::MoveReport move;                   // empty when the wall is the baseline's
    mesh::MoveHistory history;               // every increment's grid and displacement (for the
                                             // mesh adjoint; empty when not moved)
    bool moved = false;                      // false when the shape's wall is the baseline's
    mesh::QualitySummary quality;
    mesh::SpacingJump spacingJump;
    mesh::WallBend wallBend;                 // the sharpest turn of the wall from node to node
};

/// Largest ratio of neighbouring grid spacings accepted without a warning (the evaluation still
/// runs): central differences lose their accuracy across such a jump and solves tend to stall.
inline constexpr double kSpacingJumpWarning = 8.0;

/// A wall that turns by more than this many degrees from one grid node to the next is not
/// resolved by the grid (a fold or a bend tighter than the spacing): a warning before the solve,
/// and named in the reason of a flow that does not converge.
inline constexpr double kWallBendWarning = 25.0;

/// The wall bend for a human: how sharp, where, and what resolves it.
std::string describeWallBend(const mesh::WallBend& b);

/// A solve stopped by flow.max_iterations is "still falling" when its residual came down by at
/// least kStillFallingFactor over its last kStillFallingWindow iterations: its reason then says
/// so (more iterations, or a restart, converge it) instead of looking for a growing mode.
inline constexpr int kStillFallingWindow = 10;
inline constexpr double kStillFallingFactor = 10.0;
/// Iterations a warm start gets past its budget (EvaluationRequest::warmIterations) when the last
/// kStillFallingWindow iterations' rate projects the tolerance within kWarmFinishMost more: the
/// projected count and two, for a step that is converging, not crawling (the optimizer's 98k
/// evaluation 13, twenty-seventh session: 4.4e-10 at its 80th iteration, a factor of 5.7 over the
/// last ten, 11 more; the thirty-fourth session's evaluation 11: 2.9e-9 at a factor of 8.7, 18
/// more, where the former limit of ten lost a flow 8.5 orders down). A crawl (2 % per iteration)
/// projects hundreds. The count is of accepted iterations; the grant is in attempts, so it is
/// scaled by the attempts per accepted iteration over the same window (a rejected attempt, whose
/// CFL is cut, counts against flow.max_iterations too), at most kWarmAttemptsPerAccepted.
inline constexpr int kWarmFinishMost = 30;
inline constexpr double kWarmAttemptsPerAccepted = 2.0;
int warmStartFinish(const flow::FlowReport& r, double relativeTolerance);

/// How many times a warm start is extended past its budget, each time as warmStartFinish grants
/// from all its iterations so far: a rate can slow on the way, and rejected attempts count
/// against the iterations granted (the thirty-fourth session's evaluation 11 got 18 more at
/// 2.9e-9, came down 6.6 instead of 8.7 times per ten iterations and stopped short, 4.4e-10 after
/// ten; renewed, it converges in 86 accepted iterations in all, to the state that the solve from
/// the free stream after the lost warm start reached in 239).
inline constexpr int kWarmExtensions = 3;

/// Extends a warm start whose budget ran out while it converged (see kWarmExtensions).
/// `report` is the budget's solve; `solve(more, cfl)` runs `more` iterations from where the last
/// solve stopped, with the CFL law's base it ended at (`cfl`, 0 for the case's); `announce(more,
/// relativeResidual)` is told before each extension. Returns the last solve's report and appends
/// the ones before it to `before` (iterations, GMRES iterations, time and history add up).
flow::FlowReport extendWarmStart(flow::FlowReport report, double relativeTolerance, flow::FlowReport& before,
                                 const std::function<flow::FlowReport(int more, double cfl)>& solve,
                                 const std::function<void(int more, double relativeResidual)>& announce);

/// The factor by which such a solve's residual fell over its last kStillFallingWindow
/// iterations; 0 when it is not still falling (another status, too short or too slow a history).
double stillFalling(const flow::FlowReport& r);

/// Whether a stage of the dissipation continuation (a factor above 1) hands its state on to the
/// next (DissipationContinuation): when it converged, or, once an earlier stage converged
/// (`started`), when it stalled or ran out of iterations below the residual it started at.
bool continuationHandsOn(const flow::FlowReport& stage, bool started);

/// A node of the flow grid, located for a human.
struct FlowLocation {
    int block = -1;
    std::string blockName;
    std::array<int, 3> node{0, 0, 0};
    std::array<double, 3> x{0, 0, 0};
    double value = 0;
    std::string boundary;  // "wall", "symmetry", "farfield", "interface", combinations, or "interior"
};

struct FlowResult {
    flow::FlowMesh mesh;
    std::vector<double> x, metrics, q;      // coordinates, metrics, state (global node order)
    flow::ResidualOptions residualOptions;  // what was solved
    flow::FlowReport report;
    struct SequencingLevel {
        long nodes = 0;                     // the level's grid nodes
        flow::FlowReport report;
    };
    std::vector<SequencingLevel> sequencing;  // grid sequencing's solves on coarser samplings of the
                                            // grid, coarsest first (flow.grid_sequencing; empty if
                                            // none); the last one stops short if one did not converge
    bool sequenced = false;                 // the solve that gave q started from the state prolonged
                                            // from them
    flow::FlowReport sequencedReport;       // a sequenced start that failed and was solved again from
                                            // the free stream (EvaluationRequest::coldRetry; else empty)
    bool warmStarted = false;               // the solve that gave q started from the warm state
    flow::FlowReport warmReport;            // a warm start that failed and was solved again from the
                                            // free stream (EvaluationRequest::coldRetry; else empty)
    bool coldRetry() const { return warmReport.iterations > 0 || !warmReport.message.empty(); }
    flow::FlowReport budgetReport;          // a warm start's first EvaluationRequest::warmIterations
                                            // and the extensions before the last, when they ran out
                                            // while Newton converged fast and the solve went on
                                            // (extendWarmStart; report: the last; else empty)
    bool sequencedRetry() const { return sequencedReport.iterations > 0 || !sequencedReport.message.empty(); }
    flow::FlowReport failedReport;          // a cold solve that failed and was solved again by
                                            // continuation in the dissipation (else empty) ...
    struct DissipationStage {
        double factor = 1;                  // kappa2 and kappa4 times this
        flow::FlowReport report;
    };
    std::vector<DissipationStage> dissipationStages;  // ... the continuation's solves, in order
                                            // (EvaluationRequest::dissipationRetry; factor 1: an
                                            // attempt at the case's own problem that failed);
                                            // `report` is then the solve of the case's own problem
                                            // that ended it
    bool dissipationRetry() const { return !dissipationStages.empty(); }
    /// Iterations of every solve of the evaluation (a failed warm start, a failed first attempt,
    /// the continuation's stages and the final solve).
    int totalIterations() const;
    int previousIterations = 0;             // a continued restart: the iterations before this run
    int checkpoints = 0;                    // restart files written during the solve
    bool restartContinued = false;          // the restart had the same free stream: same run
    long interpolatedRestart = 0;           // > 0: the restart was of another sampling of the
                                            // grid with this many nodes, interpolated onto it
    flow::ForceCoefficients forces;
    FlowLocation maxMach, maxEntropy;       // largest local Mach number, largest |s - s_inf|
    FlowLocation largestResidual;           // largest |R| per unit volume at the final state
    /// A time-accurate run (EvaluationRequest::timeAccurate): its steps, the forces after each,
    /// and what the flow does (settles, oscillates periodically, neither yet: describeUnsteadiness).
    flow::TimeAccurateReport timeAccurate;
    std::vector<flow::ForceCoefficients> timeForces;
    std::string timeVerdict;
    /// A solve that did not converge (flow.stall_modes): the linear modes of the pseudo-time
    /// dynamics at its final state (adjoint/FlowModes.h); `modesChecked` false when not looked for.
    bool modesChecked = false;
    adjoint::ModeReport modes;
    FlowLocation modeAt;                    // where the fastest-growing mode is largest (value: its
                                            // local Mach number)
};

/// What a failed continuation in the dissipation found, for the evaluation's status: down to
/// which factor a stage converged (and the case's kappa4 there) and the closest factor below it
/// that did not, or, when none converged, every stage's outcome. Empty without a continuation.
std::string continuationSummary(const FlowResult& f, double kappa4);

struct Evaluation {
    EvaluationStatus status = EvaluationStatus::Ok;
    std::string message;  // the reason, when not Ok
    bool ok() const { return status == EvaluationStatus::Ok; }
    std::vector<double> values;  // the design evaluated
    // Shape stage (always run).
    std::vector<ffd::Lattice> lattices;                // moved lattices, one per case lattice
    std::vector<ffd::InjectivityReport> injectivity;   // one per lattice
    geometry::PatchSet shape;                          // the deformed geometry
    std::vector<double> uniqueSurface;                 // its unique control points, 3 each
    // Mesh and flow stages (empty when not run).
    std::shared_ptr<MeshResult> mesh;
    std::shared_ptr<FlowResult> flow;
    double secondsShape = 0, secondsMesh = 0, secondsFlow = 0;
};

class CaseEvaluator {
public:
    /// Builds the FFD model around `baseline` (the case's geometry, loaded by the caller) and
    /// reads the case's design values. Throws GeometryError when control points cannot be
    /// embedded (unless the case allows it) and CaseError for bad values, naming the case.
    CaseEvaluator(io::CaseFile c, geometry::PatchSet baseline, const Log& log = {});
    ~CaseEvaluator();
    CaseEvaluator(const CaseEvaluator&) = delete;
    CaseEvaluator& operator=(const CaseEvaluator&) = delete;

    const io::CaseFile& caseFile() const { return case_; }
    const geometry::PatchSet& baseline() const { return baseline_; }
    /// The first FFD level; null when the case has no lattices (then the design is empty).
    const ffd::FfdModel* model() const { return model_.get(); }
    int variableCount() const;
    /// The case's own design values (its "values", baseline elsewhere).
    const std::vector<double>& caseValues() const { return caseValues_; }
    /// Design v (variableCount() values) as a case of its own: the case with v as its values
    /// (by name; those at their baseline left out), `alphaDeg` as flow.alpha when given, this
    /// description, and no outputs and no optimization section (so running it writes nothing
    /// over the study it came from). For `aeroform-cli flow` on a design of a sweep or of an
    /// optimization's history. Throws CaseError when v has the wrong size.
    io::CaseFile designCase(const std::vector<double>& v, std::optional<double> alphaDeg,
                            const std::string& description) const;
    /// The baseline control grid and its grid (extruded on first use, then kept).
    const mesh::MultiBlockMesh& baselineMesh();
    /// The baseline grid x = N b, one block each (generated on first use, then kept).
    const std::vector<mesh::StructuredGrid>& baselineGrids();
    /// The case's linear constraints on the design (constraints.symmetry, constraints.station_gap,
    /// constraints.station_second_difference),
    /// as the optimizer enforces them: lower <= row . v <= upper. Empty without a model.
    std::vector<ffd::LinearConstraint> linearConstraints() const;

    /// Runs the stages for design v (variableCount() values). Never throws for a bad design:
    /// see Evaluation::status. `cancel` is checked between stages, increments and iterations.
    Evaluation evaluate(const std::vector<double>& v, const EvaluationRequest& request = {},
                        const ProgressFn& progress = {}, const std::atomic<bool>* cancel = nullptr);

    /// The last converged flow state and its grid size (empty before the first).
    const std::vector<double>& lastConvergedState() const { return warm_; }
    void forgetWarmStart() { warm_.clear(); }
    /// The state the next warm-started flow starts from (5 per node of the case's grid; another
    /// size is ignored by evaluate): e.g. the state of a resumed optimization's last evaluation.
    void setWarmStart(std::vector<double> q) { warm_ = std::move(q); }
    /// The control-grid move's stiffness layout and buffers, kept from one evaluation to the next
    /// and shared with the gradient's mesh adjoint (the same grid topology).
    mesh::MoveWorkspace& moveWorkspace() { return moveWorkspace_; }

private:
    struct Baseline;
    void evaluateShape(Evaluation& e, const EvaluationRequest& request) const;
    void evaluateMesh(Evaluation& e, const EvaluationRequest& request, const ProgressFn& progress,
                      const std::atomic<bool>* cancel);
    void evaluateFlow(Evaluation& e, const EvaluationRequest& request, const ProgressFn& progress,
                      const std::atomic<bool>* cancel);
    // A solve that did not converge: the growing modes at its final state (f.modes, f.modeAt),
    // described for the reason ("" when none was looked for or found).
    std::string stallModes(FlowResult& f, const std::vector<double>& mach,
                           const std::function<void(const std::string&)>& say, const std::atomic<bool>* cancel) const;

    io::CaseFile case_;
    geometry::PatchSet baseline_;
    std::unique_ptr<ffd::FfdModel> model_;
    std::vector<double> caseValues_;
    std::unique_ptr<Baseline> mesh_;      // extruded baseline (and its coarser sampling)
    std::vector<double> warm_;            // last converged flow state
    mesh::MoveWorkspace moveWorkspace_;
    Log log_;
};

/// Samples the flow state q of `coarse` (a sampling of the same B-spline blocks at fewer
/// parameters) at the grid parameters of `fine` by trilinear interpolation in parameter space:
/// the initial state of a grid-sequenced solve. Both meshes must have the same blocks.
std::vector<double> prolongState(const mesh::MultiBlockMesh& coarse, const flow::FlowMesh& coarseFlow,
                                 const std::vector<double>& q, const mesh::MultiBlockMesh& fine,
                                 const flow::FlowMesh& fineFlow);

/// Per block, the grid-node parameters along i, j, k (mesh::GridBlock::samples, as a restart
/// file records them: io::RestartInfo::samples).
using GridParameters = std::vector<std::array<std::vector<double>, 3>>;
GridParameters gridParameters(const mesh::MultiBlockMesh& m);

/// Records in `info` what lets a restart start another sampling of the grid: m's grid parameters
/// and fm's block corners at the node coordinates x (3 per node).
void recordGrid(io::RestartInfo& info, const mesh::MultiBlockMesh& m, const flow::FlowMesh& fm, const std::vector<double>& x);

/// The state q given at the nodes of blocks sampled at `from` (blocks one after the other, i
/// fastest) interpolated trilinearly in parameter space at the nodes of `toFlow`, sampled at
/// `to`; parameters outside `from`'s range take its end values. Any two samplings of the same
/// blocks, finer or coarser (a restart carried to another mesh.refine); throws Error when the
/// block counts or sizes do not match.
std::vector<double> interpolateState(const GridParameters& from, const std::vector<double>& q, const GridParameters& to,
                                     const flow::FlowMesh& toFlow);

}  // namespace aero::study
