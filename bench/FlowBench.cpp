// Flow solver costs on the half-sphere grids. Run: OMP_WAIT_POLICY=passive build/release/bench/bench_flow
//  - residual evaluation (double) and its throughput in nodes/s, on 1 and 2 threads (the
//    OpenMP speed-up is the ratio of the two in the same run);
//  - exact Jacobian assembly (coloured complex step); a matrix-free exact Jacobian-vector
//    product; the block ILU(1) factorization and solve of the preconditioner (args: threads,
//    parts of its ordering; 1 part = natural order, sequential);
//  - a full solve of the small half-sphere grid (Mach 0.5, 11,340 nodes) with iterations,
//    GMRES iterations and peak memory as counters (args: threads, ILU parts);
//  - a time-accurate run of it from the free stream, with and without the lagged preconditioner.
// Grids: "small" = coarse level at refine 0.5, farfield 5, wall spacing 0.05 (the solver test's);
// "coarse" = the coarse level itself (75,140 nodes, farfield 20).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <map>
#include <memory>

#include "common/Memory.h"
#include "flow/BlockIlu.h"
#include "flow/FlowSolver.h"
#include "flow/Jacobian.h"
#include "flow/Metrics.h"
#include "flow/TimeAccurate.h"
#include "geometry/HalfSphere.h"
#include "mesh/Extrusion.h"

using namespace aero;

namespace {

struct Grid {
    flow::FlowMesh fm;
    std::vector<double> metrics;
};

const Grid& grid(const std::string& name) {
    static std::map<std::string, std::unique_ptr<Grid>> cache;
    auto& slot = cache[name];
    if (!slot) {
        mesh::ExtrusionOptions o = mesh::extrusionLevel("coarse");
        if (name == "small") {
            o.refine = 0.5;
            o.gridWallSpacing = 0.05;
            o.farfieldRadius = 5;
        }
        const mesh::MultiBlockMesh m = mesh::extrudeToFarfield(geometry::makeHalfSphere(), o);
        const auto grids = mesh::regenerateAll(m);
        slot = std::make_unique<Grid>();
        slot->fm = flow::makeFlowMesh(m, grids);
        slot->metrics = flow::computeMetrics(slot->fm, flow::gatherCoordinates(slot->fm, grids));
    }
    return *slot;
}

// A smooth, non-uniform state (the free stream plus a bump), so nothing is trivially zero.
std::vector<double> state(const flow::FlowMesh& fm, const flow::FreeStream& fs) {
    std::vector<double> q = flow::freeStreamState(fm, fs);
    for (long n = 0; n < fm.nodeCount; ++n) {
        const double w = 0.02 * std::sin(0.001 * static_cast<double>(n));
        q[flow::kVars * n] *= 1 + w;
        q[flow::kVars * n + 1] *= 1 - w;
    }
    return q;
}

void BM_Residual(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    const int threads = static_cast<int>(st.range(0));
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    flow::ResidualOptions o;
    const std::vector<double> q = state(g.fm, o.freeStream);
    std::vector<double> r(q.size());
    for (auto _ : st) {
        flow::residual(g.fm, g.metrics.data(), q.data(), o, r.data());
        benchmark::DoNotOptimize(r.data());
    }
    omp_set_num_threads(before);
    st.counters["nodes"] = static_cast<double>(g.fm.nodeCount);
    st.SetItemsProcessed(st.iterations() * g.fm.nodeCount);
}
BENCHMARK_CAPTURE(BM_Residual, coarse, "coarse")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ExactJacobian(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    flow::ResidualOptions o;
    const std::vector<double> q = state(g.fm, o.freeStream);
    flow::BlockSparseMatrix J = flow::jacobianPattern(g.fm, 2);
    for (auto _ : st) {
        flow::assembleJacobian(g.fm, g.metrics, q.data(), o, J);
        benchmark::DoNotOptimize(J.values.data());
    }
    st.counters["nodes"] = static_cast<double>(g.fm.nodeCount);
    st.counters["blocks_stored"] = static_cast<double>(J.blockCount());
}
BENCHMARK_CAPTURE(BM_ExactJacobian, coarse, "coarse")->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

void BM_JacobianProduct(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    flow::ResidualOptions o;
    const std::vector<double> q = state(g.fm, o.freeStream);
    flow::JacobianProduct jp(g.fm, g.metrics, o);
    jp.setState(q.data());
    std::vector<double> v(q.size(), 1e-3), out(q.size());
    for (auto _ : st) {
        jp.mult(v.data(), out.data());
        benchmark::DoNotOptimize(out.data());
    }
    st.SetItemsProcessed(st.iterations() * g.fm.nodeCount);
}
BENCHMARK_CAPTURE(BM_JacobianProduct, coarse, "coarse")->Unit(benchmark::kMillisecond)->UseRealTime();

// The preconditioner of one Newton iteration: approximate Jacobian + time-step diagonal, then
// the block ILU factorization, then one ILU solve; args: threads, parts of the ILU ordering
// (1 = the natural order, sequential).
struct Preconditioner {
    flow::BlockSparseMatrix P;
    flow::BlockIlu ilu;
};

Preconditioner preconditioner(const Grid& g, int parts) {
    flow::ResidualOptions o;
    o.lumpedDissipation = true;
    o.freezeCoefficients = true;
    const std::vector<double> q = state(g.fm, o.freeStream);
    Preconditioner pc;
    pc.P = flow::jacobianPattern(g.fm, 1);
    flow::assembleApproximateJacobian(g.fm, g.metrics, q.data(), o, pc.P);
    pc.P.addDiagonal(flow::timeStepScale(g.fm, g.metrics, q.data(), o.freeStream.gamma).data());
    if (parts > 1) pc.ilu.setOrdering(flow::partitionOrdering(pc.P, flow::blockGroups(g.fm, parts), parts));
    return pc;
}

void BM_IluFactor(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    const int before = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(st.range(0)));
    Preconditioner pc = preconditioner(g, static_cast<int>(st.range(1)));
    for (auto _ : st) {
        if (!pc.ilu.factor(pc.P, flow::NewtonOptions{}.iluFill)) st.SkipWithError(pc.ilu.message().c_str());
    }
    omp_set_num_threads(before);
    st.counters["ilu_blocks"] = static_cast<double>(pc.ilu.storedBlocks());
    st.counters["separator_rows"] = static_cast<double>(pc.ilu.ordering().partStart.back() - pc.ilu.ordering().partStart.end()[-2]);
}
BENCHMARK_CAPTURE(BM_IluFactor, coarse, "coarse")->Args({1, 1})->Args({1, 2})->Args({2, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_IluSolve(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    const int before = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(st.range(0)));
    Preconditioner pc = preconditioner(g, static_cast<int>(st.range(1)));
    pc.ilu.setPrecision(static_cast<flow::IluPrecision>(st.range(2)));
    if (!pc.ilu.factor(pc.P, flow::NewtonOptions{}.iluFill)) st.SkipWithError(pc.ilu.message().c_str());
    std::vector<double> b(flow::kVars * g.fm.nodeCount, 1.0), x(b.size());
    for (auto _ : st) {
        pc.ilu.solve(b.data(), x.data());
        benchmark::DoNotOptimize(x.data());
    }
    omp_set_num_threads(before);
}
// args: threads, parts, storage of the factors (IluPrecision: 0 double, 1 single, 2 bfloat16)
BENCHMARK_CAPTURE(BM_IluSolve, coarse, "coarse")->Args({1, 1, 1})->Args({1, 2, 1})->Args({2, 2, 0})->Args({2, 2, 1})->Args({2, 2, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SolveHalfSphere(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    const int threads = static_cast<int>(st.range(0));
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    flow::ResidualOptions o;
    flow::NewtonOptions n;
    n.preconditionerParts = static_cast<int>(st.range(1));
    flow::FlowReport rep;
    for (auto _ : st) {
        std::vector<double> q;
        rep = flow::solveFlow(g.fm, g.metrics, o, q, n);
        benchmark::DoNotOptimize(q.data());
    }
    omp_set_num_threads(before);
    st.counters["nodes"] = static_cast<double>(g.fm.nodeCount);
    st.counters["converged"] = rep.converged();
    st.counters["newton_iterations"] = rep.iterations;
    st.counters["gmres_iterations"] = rep.linearIterations;
    st.counters["orders"] = std::log10(rep.initialResidual / rep.finalResidual);
    st.counters["peak_memory_mb"] = peakMemoryMb();
}
BENCHMARK_CAPTURE(BM_SolveHalfSphere, small, "small")->Args({1, 1})->Args({2, 1})->Args({2, 2})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// A time-accurate run (flow/TimeAccurate.h) of the small half-sphere from the free stream (an
// impulsive start): 20 steps of 0.5. args: threads, whether the inner iterations keep the step's
// preconditioner (1) or assemble and factor it every iteration (0).
void BM_TimeAccurateHalfSphere(benchmark::State& st, const char* name) {
    const Grid& g = grid(name);
    const int threads = static_cast<int>(st.range(0));
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    flow::ResidualOptions o;
    flow::NewtonOptions n;
    flow::TimeAccurateOptions t;
    t.timeStep = 0.5;
    t.steps = 20;
    t.lagPreconditioner = st.range(1) != 0;
    flow::TimeAccurateReport rep;
    for (auto _ : st) {
        std::vector<double> q;
        rep = flow::solveTimeAccurate(g.fm, g.metrics, o, q, n, t);
        benchmark::DoNotOptimize(q.data());
    }
    omp_set_num_threads(before);
    int inner = 0;
    for (const auto& r : rep.history) inner += r.innerIterations;
    st.counters["nodes"] = static_cast<double>(g.fm.nodeCount);
    st.counters["completed"] = rep.completed;
    st.counters["steps"] = static_cast<double>(rep.history.size());
    st.counters["inner_iterations"] = inner;
    st.counters["gmres_iterations"] = rep.linearIterations;
    st.counters["peak_memory_mb"] = peakMemoryMb();
}
BENCHMARK_CAPTURE(BM_TimeAccurateHalfSphere, small, "small")->Args({1, 1})->Args({1, 0})->Args({2, 1})->Args({2, 0})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
