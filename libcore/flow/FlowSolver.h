#pragma once
// Steady Euler solution R(q) = 0 (the paper's Eq. 8) by pseudo-transient continuation turning
// into inexact Newton (Section IV.A): each iteration solves
//   (V/dt + dR/dq) dq = -R(q),   V/dt = sum_d (|m_d . u| + c |m_d|) / CFL  (local time steps),
//   CFL = base max(1, (R0 / R)^beta) (capped), the base growing geometrically with every full
// step and cut after a rejected one, so the CFL grows through the start-up transient (where the
// residual often rises) and with the residual's fall; the last iterations are Newton's. The
// linear systems are solved inexactly by right-preconditioned GMRES with a block ILU(iluFill) of
// the approximate Jacobian (lumped first-order dissipation, frozen coefficients) plus V/dt; the
// system matrix is that approximate Jacobian itself in the start-up (cheap products) and the
// exact one (Jacobian-vector products by complex step, Jacobian.h) once the residual is below
// exactBelow or the approximate steps crawl (NewtonOptions); after an exact step's linear solve
// fails, exact steps that do not reach a new best residual within recoveryIterations hand over
// to approximate ones again.
// The solver never returns a silent wrong answer: the report says why it stopped.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "flow/BlockIlu.h"
#include "flow/FlowMesh.h"
#include "flow/Gmres.h"
#include "flow/Jacobian.h"
#include "flow/Residual.h"

namespace aero::flow {

struct NewtonOptions {
    double relativeTolerance = 1e-10;  // stop when ||R|| <= tol ||R0||
    double absoluteTolerance = 1e-14;  // ... or ||R|| (L2 over all nodes) <= this
    int maxIterations = 300;           // nonlinear iterations (accepted or rejected)
    double maxSeconds = 0;             // > 0: the solve stops (FlowStatus::TimeLimit) before an
                                       // iteration once this much wall time has passed since it
                                       // began (the case's flow.max_seconds, shared by the stage's
                                       // solves: study::CaseEvaluator)
    double cfl0 = 2.0;                 // initial CFL
    double cflGrowth = 1.2;            // CFL base grows by this after every full step
    double cflExponent = 1.0;          // CFL = base max(1, (R0/R)^beta)
    double cflMax = 1e12;              // CFL cap (1e12: effectively Newton)
    double cflBackoff = 0.5;           // the CFL base is multiplied by this after a step whose GMRES
                                       // missed its tolerance by more than backoffMiss (accepted,
                                       // but a sign that the next, larger CFL would be harder still)
    double backoffMiss = 2.0;          // ... times the tolerance. 1 (any miss) halved the CFL after
                                       // steps whose deflated GMRES ended at a true residual of
                                       // 0.051-0.07 against 0.05 (the estimate it stops on drifts
                                       // over deflated cycles): good steps, but the backed-off CFL
                                       // held the coarse optimum's 98k flow in exact/approximate
                                       // pairs (30 iterations, 3,413 GMRES; 17, 2,036 with 2) and
                                       // an ILU(2) solve of it at CFL 300 (docs/performance.md)
    double cflMaxIncrease = 4.0;       // the CFL of an iteration at most this times the last
                                       // accepted one's (the (R0/R) factor can jump 5x in a step)
    double linearTolerance = 0.05;     // GMRES relative tolerance (forcing term)
    int gmresRestart = 60;
    int gmresMaxIterations = 180;      // per nonlinear iteration (3 restart cycles)
    int gmresDeflation = 20;           // harmonic Ritz vectors kept over a restart (GMRES-DR: on the
                                       // 98k blended wing a steady system to 1e-10 takes 415 products
                                       // against > 3000 with plain GMRES(60); docs/performance.md)
    bool gmresSingleBasis = false;     // the Krylov basis in float (GmresOptions::singleBasis): the
                                       // same iterations on the 98k samples and 17 % less memory,
                                       // but a different path on hard designs (one random design
                                       // of the robustness suite stalls with it); opt-in below
                                       // lowMemoryNodes, always on from there (docs/performance.md)
    double gmresReorthogonalizeBelow = 0.1;  // a Newton step's Gram-Schmidt pass is repeated
                                       // where it left the new vector shorter than this fraction
                                       // of its length (GmresOptions::reorthogonalizeBelow): at a
                                       // Newton step's tolerance a second pass is needed only
                                       // after such a cancellation (the adjoint keeps DGKS's 0.71;
                                       // docs/performance.md)
    IluPrecision iluPrecision = IluPrecision::Single;  // storage of the preconditioner's
                                       // factors; Bfloat16 halves their memory (0.75 GB on the
                                       // 903k paper grid) with the same iterations on the samples,
                                       // but like the float basis it moves hard designs' paths at
                                       // round-off level: opt-in below lowMemoryNodes, always
                                       // Bfloat16 from there (docs/performance.md)
    int lowMemoryNodes = 50000;        // from this many grid nodes on, the approximate Jacobian
                                       // is kept after its ILU is factored only in float and only
                                       // for approximate steps (exact steps free it), and every
                                       // step frees the Krylov basis before the next assembly, so
                                       // the matrix (1.3 GB on the 903k paper grid) and the basis
                                       // (1.1-2.2 GB) are not held at full size together; and the
                                       // ILU factors are stored in bfloat16 and the basis in float
                                       // (whatever iluPrecision and gmresSingleBasis say): the
                                       // paper grid in 3.59 GB instead of 6.32 GB, the same
                                       // iterations; the 75k half-sphere in 273 MB instead of 479
                                       // and 0.93x the time (300,000 until the thirty-third
                                       // session; the 14k grids of the robustness suite stay
                                       // below it) (0: always; docs/performance.md)
    ProductMode products = ProductMode::Difference;  // the exact phase's Jacobian-vector
                                       // products: a real residual's difference (3.5x cheaper than
                                       // a complex one; Jacobian.h) or complex step
    double maxRelativeChange = 0.3;    // step scaled so rho and p change by at most this fraction
    double smallStep = 0.1;            // a step scaled below this backs the CFL base off too
    bool localCfl = false;             // per-node CFL factors: a node the step would change (rho or p)
                                       // by more than maxRelativeChange takes its part of the step
                                       // scaled to the limit and its own time step cut by the same
                                       // factor, instead of the whole step being scaled; the factor
                                       // of every other node doubles back towards 1; so one node at
                                       // a sharp edge does not hold the whole field's step and CFL
                                       // down (flow.local_cfl; docs/validation.md)
    double localCflFloor = 1e-3;       // smallest per-node factor
    double divergenceFactor = 1e4;     // Diverged when ||R|| > factor ||R0||
    int stallIterations = 25;          // Stalled when for this many iterations neither the best
                                       // ||R|| has improved nor the CFL reached a new high (the
                                       // start-up transient of a fine grid raises ||R|| for 40+
                                       // iterations while the full steps keep growing the CFL).
                                       // 50 was tried on the stalled random designs of the 98k
                                       // grid: none converged, each failure cost 1.5-5.6x the
                                       // time (docs/validation.md); flow.stall_iterations sets it
    double stallCflCeiling = 1e6;      // a new highest CFL counts as progress only below this: above
                                       // it the steps are Newton's and pseudo-time no longer moves,
                                       // so a growing CFL there is no sign of a transient. Without it
                                       // a design of the robustness suite cycled between relative
                                       // residuals 1e-4 and 1e-2 for 120 iterations while its CFL
                                       // climbed from 1e6 to the cap, before the stall handed it to
                                       // the dissipation continuation (docs/validation.md)
    int maxRejections = 8;             // steps rejected in a row (CFL cut by 10 each) before giving up
    int iluFill = 1;                   // level of fill of the block ILU preconditioner (ILU(2)
                                       // halves GMRES iterations but doubles the factor cost)
    double exactBelow = 1.0;           // relative residual below which the linear systems use the
                                       // exact Jacobian (inexact Newton); above it, the
                                       // approximate Jacobian itself (approximate Newton start-up);
                                       // an exact step GMRES cannot solve falls back to that.
                                       // 1: exact from the first iteration (docs/validation.md:
                                       // 18-24 iterations instead of 46-230)
    double exactCfl = 1e6;             // ... and from this CFL on, when the approximate steps
    double slowContraction = 0.8;      // reduce ||R|| by less than this factor per iteration over
    int slowWindow = 5;                // this many full steps in a row: a defect correction with
                                       // the approximate Jacobian that crawls (0.98 per iteration
                                       // on the 307k half-sphere) is handed to Newton
    int recoveryIterations = 10;       // after an exact step's GMRES failure, the exact steps that
                                       // follow have this many iterations to reach a new best
                                       // residual; if they do not, approximate steps (the
                                       // approximate Jacobian as the system matrix) take over until
                                       // they crawl and the crawl test hands back to Newton, and the
                                       // stall window restarts (once per run). The 903k half-sphere
                                       // stalled without it; a 14k design whose exact steps recover
                                       // in 3 iterations needs them (docs/validation.md). 0: never
    double switchContinuation = 0.01;  // > the residual's DissipationOptions::switchSmoothing: a
                                       // solve that starts above switchContinuationUntil first
                                       // solves the problem with the pressure switch's |.| and
                                       // max() smoothed to this width (a differentiable residual,
                                       // which Newton can converge where the kinked switch makes
                                       // the iteration wander), then continues with the case's own
                                       // switch from that state once the relative residual is
                                       // below switchContinuationUntil, or when the smooth problem
                                       // stalls or keeps rejecting steps. The answer is the case's
                                       // own residual's; 0: off (docs/validation.md)
    double switchContinuationUntil = 1e-2;  // 1e-3 and 1e-4 were tried: docs/validation.md
    double referenceResidual = 0;      // ||R0|| of the run this one continues (restart): tolerances,
                                       // exactBelow and the CFL law refer to it; 0: this run's own
    double maxLumping = 16;            // when GMRES fails on the lumped system, its lumping factor
                                       // (DissipationOptions::lumping) is doubled up to this
    double exactLumping = 0;           // > 0: the lumping factor of the exact (Newton) steps'
                                       // preconditioner from exactLumpingCfl on, while the run's own
                                       // lumping is still the option's (not raised after a GMRES
                                       // failure): an operator nearer the exact Jacobian for the
                                       // last orders. Measured at 2.5 (docs/performance.md): the
                                       // hardest cold 98k design 34 -> 20 iterations, but the
                                       // 14.6k robustness suite 1.19x the GMRES and the paper grid
                                       // 1.06x: it reshuffles the chaotic end of the path rather
                                       // than shortening it, so it is not the default. 0: the
                                       // run's lumping throughout
    double exactLumpingCfl = 1e6;
    double linearFailure = 0.5;        // a step whose GMRES reduced the linear residual by less
                                       // than this factor is rejected (CFL cut) instead of taken
    double finalForcing = 0.25;        // the last Newton step's GMRES tolerance at most: when
                                       // linearTolerance would take the residual past the
                                       // tolerance by more than needed, and the step before (exact,
                                       // full) reduced it by more than the factor left to go, GMRES
                                       // solves only to half that factor (capped here) instead of
                                       // linearTolerance (the 75k half-sphere's last step: 34
                                       // GMRES iterations for a factor of 2.4; docs/performance.md).
                                       // The step before solves to half the factor needed when
                                       // that is 1 to 8 times tighter than linearTolerance and
                                       // its own predecessor followed its forcing term, so that it
                                       // is the last (FlowSolver.cpp, kReachInOneStep).
                                       // 0: always linearTolerance
    int preconditionerParts = 2;       // > 1: the ILU factors and solves this many groups of mesh
                                       // blocks in parallel, their coupling kept through a
                                       // separator ordered last (BlockIlu.h); fixed rather than
                                       // the thread count, so a run's iterations are the same on
                                       // any machine. 2: on 2 cores the 75k half-sphere takes 50 s
                                       // instead of 72 s (366 GMRES instead of 343); 1 is the
                                       // natural order, sequential (docs/performance.md)
};

enum class FlowStatus { Converged, MaxIterations, Stalled, Diverged, NotANumber, Cancelled, TimeLimit };
const char* flowStatusName(FlowStatus s);

struct FlowIteration {
    int iteration = 0;
    double residual = 0;          // ||R(q)||_2 before the step
    double relativeResidual = 0;  // residual / ||R0||
    double cfl = 0;
    int linearIterations = 0;
    double linearResidual = 0;    // GMRES relative residual reached
    double linearTarget = 0;      // ... and the tolerance it aimed at (0: linearTolerance)
    double stepScale = 1;         // fraction of the Newton step taken
    bool exact = false;           // the step solved with the exact Jacobian (Newton)
    double seconds = 0;           // since the start
    std::string rejected;         // non-empty: this attempt was rejected, and why (the iteration
                                  // is tried again with a smaller CFL or more lumping; not in
                                  // FlowReport::history)
};

struct FlowReport {
    FlowStatus status = FlowStatus::MaxIterations;
    std::string message;          // the reason, in words
    std::vector<FlowIteration> history;
    int iterations = 0;
    int linearIterations = 0;
    double initialResidual = 0, finalResidual = 0;
    double seconds = 0;
    double cflBase = 0;           // the CFL law's base at the end (a restart continues with it)
    double lumping = 0;           // the preconditioner's lumping factor at the end (raised from
                                  // the option's when GMRES failed on the lumped system)
    int approximateFrom = 0;      // the iteration from which approximate steps took over because
                                  // the exact ones did not recover from a failed linear solve
                                  // (NewtonOptions::recoveryIterations; 0: they did not)
    int switchedAt = 0;           // the first iteration with the case's own pressure switch after
                                  // a switch continuation (0: none, or none needed)
    bool converged() const { return status == FlowStatus::Converged; }
    /// finalResidual / initialResidual (0 before a first residual).
    double relativeResidual() const { return initialResidual > 0 ? finalResidual / initialResidual : 0.0; }
};

/// The pseudo-transient continuation's CFL law: CFL = base max(1, (R0 / R)^beta), capped at
/// cflMax and at cflMaxIncrease times the last accepted step's; the base grows by cflGrowth after
/// a full step, backs off after a step whose GMRES missed its tolerance or that the change limit
/// cut to a sliver, and is cut to a tenth of the CFL actually used after a rejected attempt.
class CflLaw {
public:
    CflLaw(const NewtonOptions& o, double base) : o_(o), base_(base) {}
    /// The CFL of the next attempt at residual R (R0: the reference residual).
    double next(double R, double R0) const;
    /// After an accepted step `rec` (its cfl, linear residual and step scale).
    void accepted(const FlowIteration& rec);
    /// After a rejected attempt at CFL `cfl` and residual R.
    void rejected(double cfl, double R, double R0);
    double base() const { return base_; }

private:
    const NewtonOptions& o_;
    double base_;
    double last_ = 0;  // the CFL of the last accepted step (0: none yet)
};

/// The linear system of one pseudo-time step, (V/dt + dR/dq) dq = -R(q), and its inexact
/// solution by right-preconditioned GMRES: the system matrix is the exact Jacobian (matrix-free
/// products, JacobianProduct) or the approximate one, the preconditioner a block ILU of the
/// approximate Jacobian (lumped dissipation, frozen coefficients) plus V/dt. Built once per solve;
/// the pattern, the ILU's symbolic phase and the Krylov workspace are reused every iteration.
class StepSystem {
public:
    StepSystem(const FlowMesh& fm, const std::vector<double>& metrics, const ResidualOptions& o,
               const NewtonOptions& n);
    /// Assembles the preconditioner's matrix at state q for this CFL; `exact` selects the system
    /// matrix of solve(). r = R(q) (the difference products use it).
    void assemble(const double* q, const double* r, double cfl, bool exact);
    /// Per-node factors on the CFL (empty: 1 everywhere); used by the next assemble().
    void setLocalCfl(const std::vector<double>* factors) { local_ = factors; }
    /// A coefficient per node added to V/dt in the system matrix and the preconditioner: the
    /// physical time derivative's a0 / (J dt) of dual time stepping (TimeAccurate.h); null: none.
    /// Used by the next assemble().
    void setTimeTerm(const std::vector<double>* perNode) { time_ = perNode; }
    /// A new state for the exact products (r = R(q)), the preconditioner and the diagonal kept
    /// from the last assemble(): a Newton step with a lagged preconditioner (the inner iterations
    /// of a time step, whose Jacobian barely moves). Only after an exact assemble().
    void setState(const double* q, const double* r) {
        q_ = q;
        r_ = r;
        productsReady_ = false;
    }
    /// Factors the preconditioner; false with the reason when a pivot is singular.
    bool factor(std::string& why);
    /// dq with (V/dt + A) dq = -r, A the exact or approximate Jacobian (as assembled), GMRES to
    /// the relative tolerance given.
    GmresReport solve(const double* r, double* dq, double tolerance);
    bool exact() const { return exact_; }
    /// The approximate Jacobian as the system matrix from now on (same preconditioner; assembled
    /// again if a low-memory exact step freed it).
    void useApproximate();
    /// The residual solved from now on (the switch continuation's hand-over): the exact products
    /// and the preconditioner's approximate Jacobian follow it (its lumping is kept); assemble
    /// again before solving. No reallocation.
    void setResidualOptions(const ResidualOptions& o);
    double lumping() const { return approx_.dissipation.lumping; }
    void setLumping(double sigma) { approx_.dissipation.lumping = sigma; }

private:
    const FlowMesh& fm_;
    const std::vector<double>& metrics_;
    const NewtonOptions& n_;
    ResidualOptions approx_;
    BlockSparseMatrix P_;
    BlockIlu ilu_;
    JacobianProduct jp_;
    GmresWorkspace krylov_;
    std::vector<double> d_, rhs_;  // V/dt per node; -R
    const double* q_ = nullptr;
    const double* r_ = nullptr;
    const std::vector<double>* local_ = nullptr;
    const std::vector<double>* time_ = nullptr;
    bool exact_ = false;
    bool factored_ = false;       // ilu_ holds the factors of the last assemble()
    bool productsReady_ = false;  // jp_ holds the state of the last assemble()
    bool lowMemory_ = false;      // NewtonOptions::lowMemoryNodes reached
    bool matrixLent_ = false;     // P_'s values hold the Krylov basis (a low-memory exact step)
    std::size_t sharedDoubles_ = 0;  // low memory: P_'s capacity, room for either P_ or the basis
    double optionLumping_ = 0;    // the residual options' lumping factor (before any raise)
    double matrixLumping_ = 0;    // the lumping factor P_ was last assembled with

    void assembleMatrix();        // P_ = the approximate Jacobian at q_ + diag(d_)
    void reclaimMatrix();         // P_'s values back from the Krylov basis (contents undefined)
};

/// Solves R(q) = 0 on the mesh. q: 5 per node; if empty on entry it starts from the free stream
/// of o.freeStream; on return it holds the last accepted iterate (whatever the status).
/// progress: called after every accepted iteration and every rejected attempt (rejected set);
/// cancel: checked between iterations; checkpoint: called after every accepted iteration with
/// the state and the report so far (its iterations, residuals, CFL base and lumping: what a
/// restart needs), so a caller can save the run's progress (the caller decides how often).
using FlowCheckpoint = std::function<void(const std::vector<double>& q, const FlowReport& sofar)>;
FlowReport solveFlow(const FlowMesh& fm, const std::vector<double>& metrics,
                     const ResidualOptions& o, std::vector<double>& q, const NewtonOptions& n = {},
                     const std::function<void(const FlowIteration&)>& progress = {},
                     const std::atomic<bool>* cancel = nullptr, const FlowCheckpoint& checkpoint = {});

/// sum_d (|m_d . u| + c |m_d|) at every node (the V/dt of CFL = 1).
std::vector<double> timeStepScale(const FlowMesh& fm, const std::vector<double>& metrics,
                                  const double* q, double gamma);

/// The relative change of density and pressure per node (the larger of the two) that the step
/// dq makes at q: the quantity NewtonOptions::maxRelativeChange limits.
void relativeChanges(long nodes, const double* q, const double* dq, double gamma, std::vector<double>& out);

/// Whether every node has rho > 0 and p > 0 (and finite values); `where` gets the first bad node.
bool isPhysical(const FlowMesh& fm, const double* q, double gamma, long* where = nullptr);

}  // namespace aero::flow
