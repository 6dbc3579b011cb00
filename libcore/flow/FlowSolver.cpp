#include "flow/FlowSolver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>

#include "common/Error.h"
#include "flow/ChunkedSum.h"
#include "flow/Metrics.h"

namespace aero::flow {

namespace {

// The step before the last one solves GMRES further when the tolerance needs at most this factor
// times the forcing term (a few more GMRES iterations: 8 is 0.7 more orders against 1.3), and the
// step before it reduced the residual by at least its forcing term divided by kFollowedForcing.
constexpr double kReachInOneStep = 1.0 / 8;
constexpr double kFollowedForcing = 1.5;

// In fixed chunks (ChunkedSum.h): the residual's norm steers the CFL law and the step tests, so a
// sum that depended on the thread count sent the robustness study's creased designs down
// different paths on 1 and 2 threads (the 98k random design 8 converged on one, not on two).
double norm2(const std::vector<double>& v) {
    return std::sqrt(chunkedDot(static_cast<long>(v.size()), v.data(), v.data()));
}

std::string sci(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3e", x);
    return buf;
}

// A solve whose residual is within kRoundOffStall times its round-off level and has made no
// progress for kRoundOffWindow iterations has converged as far as double precision allows.
constexpr int kRoundOffStall = 10;
constexpr int kRoundOffWindow = 5;

// The residual's round-off level at q: ||R(q + d) - R(q)|| with every state value moved by one
// unit in the last place (d_k = eps q_k s_k, s_k = +-1 by a hash of k). A state rounded to double
// precision is that far from the exact one, so no tolerance below this residual can be met; a
// solve that stalls within a small factor of it has converged as far as the arithmetic allows.
double roundOffResidual(const FlowMesh& fm, const std::vector<double>& metrics, const std::vector<double>& q,
                        const ResidualOptions& o) {
    const long n = static_cast<long>(q.size());
    std::vector<double> qd(q), r(n), rd(n);
    const double eps = std::numeric_limits<double>::epsilon();
    for (long k = 0; k < n; ++k) {
        const bool up = ((static_cast<unsigned long>(k) * 2654435761UL) >> 16) & 1UL;
        qd[k] += (up ? eps : -eps) * q[k];
    }
    residual(fm, metrics.data(), q.data(), o, r.data());
    residual(fm, metrics.data(), qd.data(), o, rd.data());
    for (long k = 0; k < n; ++k) rd[k] -= r[k];
    return norm2(rd);
}

std::string fixedSeconds(double s) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g s", s);
    return buf;
}

}  // namespace

const char* flowStatusName(FlowStatus s) {
    switch (s) {
        case FlowStatus::Converged:
            return "converged";
        case FlowStatus::MaxIterations:
            return "max-iterations";
        case FlowStatus::Stalled:
            return "stalled";
        case FlowStatus::Diverged:
            return "diverged";
        case FlowStatus::NotANumber:
            return "nan";
        case FlowStatus::Cancelled:
            return "cancelled";
        case FlowStatus::TimeLimit:
            return "time-limit";
    }
    return "unknown";
}

std::vector<double> timeStepScale(const FlowMesh& fm, const std::vector<double>& metrics,
                                  const double* q, double gamma) {
    std::vector<double> s(fm.nodeCount);
#pragma omp parallel for schedule(static)
    for (long n = 0; n < fm.nodeCount; ++n) {
        double sum = 0;
        for (int d = 0; d < 3; ++d) sum += spectralRadius(q + kVars * n, &metrics[kMetricWidth * n + 3 * d], gamma);
        s[n] = sum;
    }
    return s;
}

void relativeChanges(long nodes, const double* q, const double* dq, double gamma, std::vector<double>& out) {
    out.resize(nodes);
#pragma omp parallel for schedule(static)
    for (long n = 0; n < nodes; ++n) {
        const double* a = q + kVars * n;
        double b[kVars];
        for (int v = 0; v < kVars; ++v) b[v] = a[v] + dq[kVars * n + v];
        const double pa = pressure(a, gamma), pb = pressure(b, gamma);
        out[n] = std::max(std::abs(b[0] - a[0]) / a[0], std::abs(pb - pa) / pa);
    }
}

bool isPhysical(const FlowMesh& fm, const double* q, double gamma, long* where) {
    for (long n = 0; n < fm.nodeCount; ++n) {
        const double* a = q + kVars * n;
        bool ok = true;
        for (int v = 0; v < kVars; ++v) ok = ok && std::isfinite(a[v]);
        ok = ok && a[0] > 0 && pressure(a, gamma) > 0;
        if (!ok) {
            if (where) *where = n;
            return false;
        }
    }
    return true;
}

double CflLaw::next(double R, double R0) const {
    double cfl = std::min(o_.cflMax, base_ * std::max(1.0, std::pow(R0 / R, o_.cflExponent)));
    if (last_ > 0) cfl = std::min(cfl, o_.cflMaxIncrease * last_);
    return cfl;
}

void CflLaw::accepted(const FlowIteration& rec) {
    last_ = rec.cfl;
    if (rec.linearResidual > o_.backoffMiss * std::max(o_.linearTolerance, rec.linearTarget)) {
        // GMRES stopped well short of the forcing tolerance: the system is too hard for the
        // preconditioner at this CFL. Step back instead of growing into harder systems. (A
        // miss by a few percent is the drift of deflated GMRES's estimate, not a hard system.)
        base_ *= o_.cflBackoff;
    } else if (rec.stepScale == 1.0) {
        base_ = std::min(o_.cflMax, o_.cflGrowth * base_);
    } else if (rec.stepScale < o_.smallStep) {
        // The change limit cut the step to a sliver: the linearization is not trusted this
        // far out. Without a smaller CFL the same sliver repeats (the medium level's blended
        // wing sat at step 0.00 for 25 iterations).
        base_ *= o_.cflBackoff;
    }
}

void CflLaw::rejected(double cfl, double R, double R0) {
    // Cut the CFL actually used (not only the base: near convergence the (R0/R) factor would
    // keep the product at cflMax and the cut would do nothing). The floor bounds that CFL, not the
    // base: a floor on the base times a factor of 1e9 gave back the rejected CFL itself, capped at
    // cflMaxIncrease times the last accepted step's, and the 98k random 2 design repeated the same
    // rejected step nine times at a relative residual of 1.5e-9.
    const double cut = std::max(1e-3 * o_.cfl0, 0.1 * cfl);
    base_ = cut / std::max(1.0, std::pow(R0 / R, o_.cflExponent));
}

StepSystem::StepSystem(const FlowMesh& fm, const std::vector<double>& metrics, const ResidualOptions& o,
                       const NewtonOptions& n)
    : fm_(fm), metrics_(metrics), n_(n), approx_(o), P_(jacobianPattern(fm, 1)),
      jp_(fm, metrics, o, n.products), rhs_(kVars * static_cast<std::size_t>(fm.nodeCount)),
      lowMemory_(fm.nodeCount >= n.lowMemoryNodes), optionLumping_(o.dissipation.lumping) {
    approx_.lumpedDissipation = true;
    approx_.freezeCoefficients = true;
    // A grid where memory is the limit stores the factors in bfloat16 and the Krylov basis in float
    // (the 903k paper grid: 3.59 GB against 6.32 GB, the same iterations; docs/performance.md).
    ilu_.setPrecision(lowMemory_ ? IluPrecision::Bfloat16 : n.iluPrecision);
    if (lowMemory_) {
        // One block holds the approximate Jacobian while it is assembled and factored, and an
        // exact step's Krylov basis while GMRES runs (GmresWorkspace::lend): room for the larger.
        const std::size_t basis = GmresWorkspace::singleBytes(kVars * fm.nodeCount, std::max(1, n.gmresRestart) + 1);
        sharedDoubles_ = std::max(P_.values.size(), (basis + sizeof(double) - 1) / sizeof(double));
        P_.values.reserve(sharedDoubles_);
    }
    if (n.preconditionerParts > 1) {
        ilu_.setOrdering(partitionOrdering(P_, blockGroups(fm, n.preconditionerParts), n.preconditionerParts));
    }
}

void StepSystem::assemble(const double* q, const double* r, double cfl, bool exact) {
    d_ = timeStepScale(fm_, metrics_, q, approx_.freeStream.gamma);
    for (double& x : d_) x /= cfl;
    if (local_ && !local_->empty()) {
        for (std::size_t i = 0; i < d_.size(); ++i) d_[i] /= (*local_)[i];
    }
    if (time_) {
        for (std::size_t i = 0; i < d_.size(); ++i) d_[i] += (*time_)[i];
    }
    // The last step's Krylov basis is not needed while the matrix is assembled and factored.
    if (lowMemory_) {
        reclaimMatrix();
        krylov_.release();
    }
    q_ = q;
    r_ = r;
    const double lumping = approx_.dissipation.lumping;
    const bool nearer = exact && n_.exactLumping > 0 && cfl >= n_.exactLumpingCfl && lumping <= optionLumping_;
    matrixLumping_ = nearer ? std::min(lumping, n_.exactLumping) : lumping;
    assembleMatrix();
    exact_ = exact;
    factored_ = false;
    productsReady_ = false;
}

void StepSystem::assembleMatrix() {
    if (lowMemory_ && P_.values.capacity() < sharedDoubles_) {
        // After an approximate step stored P_ in float: the shared block again, the float
        // values freed first (as setZero() would).
        std::vector<float>().swap(P_.singleValues);
        P_.values.reserve(sharedDoubles_);
    }
    ResidualOptions o = approx_;
    o.dissipation.lumping = matrixLumping_;
    assembleApproximateJacobian(fm_, metrics_, q_, o, P_);
    P_.addDiagonal(d_.data());
}

void StepSystem::useApproximate() {
    exact_ = false;
    // The same state, CFL and lumping as the last assemble(): the same matrix, whose factors the
    // ILU still holds. The failed step's basis first makes room for it.
    if (matrixLent_ || (!P_.hasValues() && !P_.single())) {
        reclaimMatrix();
        krylov_.release();
        assembleMatrix();
        P_.storeSingle();
    }
}

void StepSystem::reclaimMatrix() {
    if (!matrixLent_) return;
    krylov_.release();
    // The block's doubles again (the basis's floats ended them); assembly overwrites them.
    ::new (static_cast<void*>(P_.values.data())) double[P_.values.capacity()];
    matrixLent_ = false;
}

void StepSystem::setResidualOptions(const ResidualOptions& o) {
    const double lumping = approx_.dissipation.lumping;
    approx_ = o;
    approx_.lumpedDissipation = true;
    approx_.freezeCoefficients = true;
    approx_.dissipation.lumping = lumping;
    jp_.setResidualOptions(o);
    factored_ = false;
    productsReady_ = false;
}

bool StepSystem::factor(std::string& why) {
    if (factored_) return true;
    if (!ilu_.factor(P_, n_.iluFill)) {
        why = ilu_.message();
        return false;
    }
    factored_ = true;
    // An exact step's products do not use the approximate Jacobian: its block holds the basis
    // until the next assembly. An approximate step's use it rounded to float.
    if (lowMemory_) {
        if (exact_) {
            krylov_.lend(P_.values.data(), P_.values.capacity() * sizeof(double));
            matrixLent_ = true;
        } else {
            P_.storeSingle();
        }
    }
    return true;
}

GmresReport StepSystem::solve(const double* r, double* dq, double tolerance) {
    const long n = kVars * fm_.nodeCount;
    if (exact_ && !productsReady_) {
        jp_.setState(q_, r_);
        productsReady_ = true;
    }
    const LinearMap A = [&](const double* in, double* out) {
        if (!exact_) {
            P_.mult(in, out);
            return;
        }
        jp_.mult(in, out);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) out[i] += d_[i / kVars] * in[i];
    };
    const LinearMap M = [&](const double* in, double* out) { ilu_.solve(in, out); };
    // GMRES gives up once it cannot reach linearFailure at its rate so far: the step would be
    // rejected anyway (on the 75k half-sphere a failing solve took 120 iterations, 37 s).
    const GmresOptions go{n_.gmresRestart, n_.gmresMaxIterations, tolerance, n_.linearFailure,
                          n_.gmresDeflation, n_.gmresSingleBasis || lowMemory_, n_.gmresReorthogonalizeBelow};
    for (long i = 0; i < n; ++i) rhs_[i] = -r[i];
    std::fill(dq, dq + n, 0.0);
    return gmres(n, A, M, rhs_.data(), dq, go, &krylov_);
}

FlowReport solveFlow(const FlowMesh& fm, const std::vector<double>& metrics,
                     const ResidualOptions& o, std::vector<double>& q, const NewtonOptions& opt,
                     const std::function<void(const FlowIteration&)>& progress,
                     const std::atomic<bool>* cancel, const FlowCheckpoint& checkpoint) {
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const long N = fm.nodeCount, n = kVars * N;
    const double gamma = o.freeStream.gamma;
    if (q.empty()) q = freeStreamState(fm, o.freeStream);
    if (static_cast<long>(q.size()) != n || static_cast<long>(metrics.size()) != kMetricWidth * N) {
        throw Error("flow: state or metrics do not match the mesh (" + std::to_string(q.size()) +
                    " state values, " + std::to_string(metrics.size()) + " metric values for " +
                    std::to_string(N) + " nodes)");
    }
    FlowReport rep;
    auto finish = [&](FlowStatus s, const std::string& msg) {
        rep.status = s;
        rep.message = msg;
        rep.seconds = elapsed();
        return rep;
    };
    if (!isPhysical(fm, q.data(), gamma)) {
        return finish(FlowStatus::NotANumber, "the initial state has non-positive density or pressure");
    }

    std::vector<double> r(n), rNew(n), qNew(n), dq(n);
    residual(fm, metrics.data(), q.data(), o, r.data());
    double Rstart = norm2(r);
    // Relative measures refer to the first run's initial residual when this run continues one.
    const double R0 = opt.referenceResidual > 0 ? opt.referenceResidual : Rstart;
    rep.initialResidual = R0;
    rep.finalResidual = Rstart;
    if (!std::isfinite(Rstart)) return finish(FlowStatus::NotANumber, "the initial residual is not finite");
    if (Rstart <= opt.absoluteTolerance || Rstart <= opt.relativeTolerance * R0) {
        return finish(FlowStatus::Converged, "the initial state is converged (relative residual " + sci(Rstart / R0) + ")");
    }

    // Switch continuation (NewtonOptions::switchContinuation): far from the solution the
    // residual's pressure switch is made smooth (differentiable), and the case's own switch takes
    // over once the smooth problem is nearly solved, or if it stalls.
    ResidualOptions smooth = o;
    bool continuing = opt.switchContinuation > o.dissipation.switchSmoothing && o.dissipation.kappa2 > 0 &&
                      Rstart > opt.switchContinuationUntil * R0;
    if (continuing) {
        smooth.dissipation.switchSmoothing = opt.switchContinuation;
        residual(fm, metrics.data(), q.data(), smooth, r.data());
        Rstart = norm2(r);
        if (!std::isfinite(Rstart)) return finish(FlowStatus::NotANumber, "the initial residual is not finite");
    }
    const ResidualOptions* active = continuing ? &smooth : &o;
    std::vector<double> localCfl, change;
    if (opt.localCfl) localCfl.assign(N, 1.0);
    StepSystem system(fm, metrics, *active, opt);
    if (opt.localCfl) system.setLocalCfl(&localCfl);
    // With per-node CFL factors a solved step is limited node by node: a node the step would
    // change by more than the limit takes its part of the step scaled to the limit and has its
    // own time step cut by the same factor for the next iterations (the change of a short
    // pseudo-time step is about proportional to it); every other node's factor recovers. The
    // scaled update is no longer a Newton step, but it is the pseudo-transient step with those
    // nodes' time steps shortened, and near the solution, where every change is small, it is
    // the full Newton step again.
    // Returns the smallest node's scale: the CFL law sees it as the step's scale, as it would the
    // global one (a global CFL that grows while nodes are held back takes steps that are Newton
    // steps nowhere near those nodes: the refine-0.3 random 24 then wandered at CFL 1e12).
    auto limitNodes = [&] {
        double smallest = 1.0;
        for (long i = 0; i < N; ++i) {
            if (change[i] > opt.maxRelativeChange) {
                const double s = opt.maxRelativeChange / change[i];
                smallest = std::min(smallest, s);
                for (int v = 0; v < kVars; ++v) dq[kVars * i + v] *= s;
                localCfl[i] = std::max(opt.localCflFloor, localCfl[i] * s);
            } else {
                localCfl[i] = std::min(1.0, 2.0 * localCfl[i]);
            }
        }
        return smallest;
    };
    CflLaw law(opt, opt.cfl0);
    double Rn = Rstart, best = Rstart;
    rep.cflBase = law.base();
    rep.lumping = system.lumping();
    int bestIteration = 0, rejections = 0;
    double roundOff = 0;         // the residual's round-off level (roundOffResidual), measured
                                 // the first time kRoundOffWindow steps make no progress
    auto atRoundOff = [&] {
        if (roundOff == 0) roundOff = roundOffResidual(fm, metrics, q, o);
        return Rn <= kRoundOffStall * roundOff;
    };
    double cflHigh = 0;          // the largest CFL of an accepted step so far
    double lastRatio = 1.0;      // the last accepted step's ||R|| after / before, when it was a
                                 // full exact step of the case's own residual (else 1)
    bool newton = false;         // exact steps because the approximate ones crawled (sticky until
                                 // an exact step fails)
    int windowStart = 0;         // history index from which the approximate steps are judged
    // After an exact step's GMRES failure the exact steps that follow have recoveryIterations
    // to reach a new best residual; if they do not, approximate steps take over until they crawl
    // (NewtonOptions::recoveryIterations).
    int failedAt = -1;           // iteration of the exact failure being watched (-1: none)
    double bestAtFailure = 0;    // the best residual then
    bool approximateAfterFailure = false;
    // A run that stops during the continuation reports the case's own residual at its state
    // (not the smoothed problem's), so the numbers mean the same in every report.
    auto ownResidual = [&] {
        if (!continuing) return;
        residual(fm, metrics.data(), q.data(), o, r.data());
        Rn = norm2(r);
        rep.finalResidual = Rn;
    };
    // Hands the solve from the smooth switch to the case's own (its residual at this state and a
    // fresh stall window; the CFL law follows the higher residual down by itself).
    auto endContinuation = [&](int it) {
        ownResidual();
        continuing = false;
        active = &o;
        system.setResidualOptions(o);
        best = Rn;
        bestIteration = it;
        failedAt = -1;  // (Newton, if the crawl test chose it, stays: the switch is a small change)
        windowStart = static_cast<int>(rep.history.size());
        rep.switchedAt = it + 1;
    };
    for (int it = 1; it <= opt.maxIterations; ++it) {
        if (cancel && cancel->load()) {
            ownResidual();
            return finish(FlowStatus::Cancelled, "cancelled after " + std::to_string(rep.iterations) + " iterations");
        }
        if (opt.maxSeconds > 0 && elapsed() >= opt.maxSeconds) {
            ownResidual();
            return finish(FlowStatus::TimeLimit, "stopped by the time limit after " + std::to_string(rep.iterations) +
                                                     " iterations (" + fixedSeconds(elapsed()) + "): relative residual " +
                                                     sci(Rn / R0));
        }
        const double cfl = law.next(Rn, R0);
        bool exact = newton || (!approximateAfterFailure && Rn <= opt.exactBelow * R0);
        const double before = Rn;
        // The last step solves only as far as the tolerance needs: with linearTolerance (0.05)
        // a Newton step that has a factor of 2 left to go reduces the residual by 20 and pays
        // for the other 10 in GMRES iterations. Only when the step before (full, exact) already
        // reduced the residual by more than the factor needed now, so the CFL is not what
        // limits the step; if this one falls short, the next step aims at what is left (the same rule).
        // The other way round, when the step before followed its forcing term (a Newton step the
        // CFL no longer limits) and the tolerance is within a few more GMRES iterations' reach,
        // this step solves to half the factor needed, so that it is the last one: the 75k
        // half-sphere's seventh step reduced the residual by 20.6 where 51 were needed, and an
        // eighth step (25 GMRES iterations, an assembly, a factorization) did the rest.
        const double needed = std::max(opt.relativeTolerance * R0, opt.absoluteTolerance) / Rn;
        // (NewtonOptions::finalForcing 0 turns both off.)
        const bool relax = needed > opt.linearTolerance && lastRatio <= needed;
        const bool tighten = opt.finalForcing > 0 && needed <= opt.linearTolerance &&
                             needed >= kReachInOneStep * opt.linearTolerance &&
                             lastRatio <= kFollowedForcing * opt.linearTolerance;
        const double finalTolerance =
            continuing ? 0.0
                       : (relax ? std::max(opt.linearTolerance, std::min(opt.finalForcing, 0.5 * needed))
                                : (tighten ? 0.5 * needed : 0.0));
        system.assemble(q.data(), r.data(), cfl, exact);
        FlowIteration rec;
        std::string why;             // why the step was rejected
        bool linearFailed = false;   // ... because GMRES could not solve the system
        // One pseudo-time step; false when it is rejected (the CFL is then cut).
        auto step = [&]() -> bool {
            if (!system.factor(why)) {
                linearFailed = true;
                return false;
            }
            const double tolerance = exact && finalTolerance > 0 ? finalTolerance : opt.linearTolerance;
            const GmresReport g = system.solve(r.data(), dq.data(), tolerance);
            rep.linearIterations += g.iterations;
            rec = {it, Rn, Rn / R0, cfl, g.iterations, g.relativeResidual, tolerance, 1.0, exact, 0.0, {}};
            if (!(g.relativeResidual <= opt.linearFailure)) {
                linearFailed = true;
                why = "GMRES reduced the linear residual only to " + sci(g.relativeResidual) + " in " +
                      std::to_string(g.iterations) + " iterations";
                return false;
            }
            relativeChanges(N, q.data(), dq.data(), gamma, change);
            double alpha = 1.0, nodeScale = 1.0;
            if (opt.localCfl) {
                nodeScale = limitNodes();
            } else {
                const double worst = *std::max_element(change.begin(), change.end());
                if (worst > opt.maxRelativeChange) alpha = opt.maxRelativeChange / worst;
            }
            bool physical = false;
            for (int tries = 0; tries < 10 && !physical; ++tries) {
                for (long i = 0; i < n; ++i) qNew[i] = q[i] + alpha * dq[i];
                physical = isPhysical(fm, qNew.data(), gamma);
                if (!physical) alpha *= 0.5;
            }
            if (!physical) {
                why = "the update makes density or pressure negative";
                return false;
            }
            residual(fm, metrics.data(), qNew.data(), *active, rNew.data());
            const double Rnew = norm2(rNew);
            if (!std::isfinite(Rnew) || Rnew > 10.0 * Rn) {
                why = "the residual would grow to " + sci(Rnew / R0) + " of the initial one";
                return false;
            }
            q.swap(qNew);
            r.swap(rNew);
            Rn = Rnew;
            rec = {it, Rn, Rn / R0, cfl, g.iterations, g.relativeResidual, tolerance, alpha * nodeScale, exact, elapsed(), {}};
            return true;
        };
        // A rejected attempt is reported too: the retries (more lumping, a smaller CFL) can take
        // long on a big grid, and a silent minute looks like a hang.
        auto attempt = [&]() -> bool {
            rec = {it, Rn, Rn / R0, cfl, 0, 0.0, 0.0, 0.0, exact, 0.0, {}};
            if (step()) return true;
            rec.seconds = elapsed();
            rec.rejected = why;
            if (progress) progress(rec);
            return false;
        };
        bool accepted = attempt();
        if (!accepted && exact) {
            // The exact system was too hard for the preconditioner at this CFL: take an
            // approximate-Newton step instead before cutting the CFL; a crawl of approximate
            // steps has to show itself again before the next exact one.
            if (linearFailed && failedAt < 0 && !approximateAfterFailure && opt.recoveryIterations > 0) {
                failedAt = it;
                bestAtFailure = best;
            }
            exact = false;
            newton = false;
            windowStart = static_cast<int>(rep.history.size()) + 1;
            linearFailed = false;
            system.useApproximate();
            accepted = attempt();
        }
        while (!accepted && linearFailed && system.lumping() < opt.maxLumping) {
            // GMRES failed on the lumped system: its ILU lost stability (too little diagonal
            // dominance for this grid and CFL). More lumping restores it; keep it for the run.
            system.setLumping(std::min(opt.maxLumping, 2.0 * system.lumping()));
            rep.lumping = system.lumping();
            exact = false;
            system.assemble(q.data(), r.data(), cfl, false);
            linearFailed = false;
            accepted = attempt();
        }
        if (!accepted) {
            if (++rejections > opt.maxRejections && continuing) {
                rejections = 0;
                endContinuation(it);
                continue;
            }
            if (rejections > opt.maxRejections) {
                return finish(FlowStatus::Diverged, "diverged: " + std::to_string(rejections) +
                                                        " steps in a row rejected (last at CFL " + sci(cfl) + ": " + why +
                                                        "), relative residual " + sci(Rn / R0));
            }
            law.rejected(cfl, Rn, R0);
            rep.cflBase = law.base();
            continue;
        }
        rejections = 0;
        lastRatio = (rec.exact && rec.stepScale == 1.0 && active == &o) ? Rn / before : 1.0;
        law.accepted(rec);
        rep.cflBase = law.base();
        ++rep.iterations;
        rep.finalResidual = Rn;
        rep.history.push_back(rec);
        if (progress) progress(rec);
        if (checkpoint) {
            rep.seconds = elapsed();
            checkpoint(q, rep);
        }
        if (continuing && Rn <= opt.switchContinuationUntil * R0) {
            endContinuation(it);
            if (!(Rn <= opt.relativeTolerance * R0 || Rn <= opt.absoluteTolerance)) continue;
        }
        if (Rn <= opt.relativeTolerance * R0 || Rn <= opt.absoluteTolerance) {
            return finish(FlowStatus::Converged, "converged: residual reduced by " + sci(Rn / R0) + " in " +
                                                     std::to_string(rep.iterations) + " iterations");
        }
        if (Rn > opt.divergenceFactor * R0) {
            ownResidual();
            return finish(FlowStatus::Diverged, "diverged: residual grew to " + sci(Rn / R0) + " times the initial one");
        }
        if (Rn < 0.99 * best || (cfl > 1.01 * cflHigh && cfl < opt.stallCflCeiling)) {
            // Progress: a new best residual, or pseudo-time still advancing with a growing CFL
            // (the transient of a fine grid can raise ||R|| for 40 iterations of full steps).
            best = std::min(best, Rn);
            bestIteration = it;
        } else if (it - bestIteration >= opt.stallIterations && continuing) {
            endContinuation(it);  // the smooth problem stalled: the case's own switch from here
            continue;
        } else if (it - bestIteration >= kRoundOffWindow && active == &o && atRoundOff()) {
            // A tolerance below the arithmetic's reach (1e-12 on the 98k optimization grid, whose
            // residual's round-off level is 1.6e-12 of the free stream's there; the solve stops at
            // 1.3e-12): converged as far as it can be, not a failure to retry or to look for modes.
            return finish(FlowStatus::Converged,
                          "converged to the round-off level: the residual stopped at " + sci(Rn / R0) + " after " +
                              std::to_string(rep.iterations) + " iterations, within " + std::to_string(kRoundOffStall) +
                              " times the change one unit in the last place of the state makes (" + sci(roundOff / R0) +
                              "); the tolerance " + sci(opt.relativeTolerance) + " is below it on this grid");
        } else if (it - bestIteration >= opt.stallIterations) {
            return finish(FlowStatus::Stalled, "stalled: no progress in " + std::to_string(opt.stallIterations) +
                                                   " iterations at relative residual " + sci(Rn / R0));
        }
        cflHigh = std::max(cflHigh, cfl);
        if (failedAt > 0) {
            if (Rn < 0.99 * bestAtFailure) {
                failedAt = -1;  // the exact steps recovered
            } else if (it - failedAt >= opt.recoveryIterations) {
                // They did not: on a fine grid, exact pseudo-transient steps at CFL 70-300 after
                // the failure wander (the 903k half-sphere stalled so), while approximate ones,
                // more dissipative, climb to a high CFL and hand back to Newton. The stall
                // window restarts for them, once per run.
                failedAt = -1;
                approximateAfterFailure = true;
                newton = false;
                windowStart = static_cast<int>(rep.history.size());
                if (rep.approximateFrom == 0) bestIteration = it;
                rep.approximateFrom = it + 1;
            }
        }
        if (!newton && !exact && cfl >= opt.exactCfl && opt.slowWindow > 0) {
            // Hand a crawling approximate-Newton iteration to Newton: the last slowWindow steps
            // all full, at CFL >= exactCfl, and together reducing ||R|| by less than
            // slowContraction per step.
            const int h = static_cast<int>(rep.history.size());
            const int first = h - 1 - opt.slowWindow;
            bool full = first >= windowStart;
            for (int i = first + 1; full && i < h; ++i) {
                full = rep.history[i].stepScale == 1.0 && !rep.history[i].exact && rep.history[i].cfl >= opt.exactCfl;
            }
            if (full) {
                const double rate = std::pow(Rn / rep.history[first].residual, 1.0 / opt.slowWindow);
                newton = rate > opt.slowContraction;
            }
        }
    }
    ownResidual();
    return finish(FlowStatus::MaxIterations, "not converged in " + std::to_string(opt.maxIterations) +
                                                 " iterations: relative residual " + sci(Rn / R0));
}

}  // namespace aero::flow
