// Second-level FFD costs. Run: build/release/bench/bench_mesh
//  - regeneration x = N b of the paper-size grid (903,340 nodes) and the coarse grid;
//  - the elasticity move of the control grid (m = 6) on the blended-wing deformation of
//    samples/bwb_deform.json, at the paper level (13,546 control nodes) and the coarse level;
//  - on the same deformation, node-based elasticity on the coarse grid itself (75,140 nodes):
//    the paper's point is that the control-grid route costs a few percent of that;
//  - the mesh adjoint (the move's increments in reverse, 1 and 2 functionals) and N^T.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "geometry/HalfSphere.h"
#include "io/CaseFile.h"
#include "mesh/Elasticity.h"
#include "mesh/Extrusion.h"
#include "study/CaseEvaluator.h"

using namespace aero;

namespace {

std::string samples() { return AEROFORM_SAMPLES_DIR; }

// The blended-wing deformation of the sample case (unique control points of the deformed geometry).
const std::vector<double>& bwbSurface() {
    static const std::vector<double> s = [] {
        study::CaseEvaluator ev(io::readCase(samples() + "/bwb_deform.json"), geometry::makeHalfSphere());
        study::EvaluationRequest shapeOnly;
        shapeOnly.mesh = false;
        shapeOnly.flow = false;
        return ev.evaluate(ev.caseValues(), shapeOnly).uniqueSurface;
    }();
    return s;
}

void BM_Regenerate(benchmark::State& state, const char* level) {
    const mesh::MultiBlockMesh m = mesh::extrudeToFarfield(geometry::makeHalfSphere(), mesh::extrusionLevel(level));
    std::vector<mesh::StructuredGrid> grids;
    for (auto _ : state) {
        mesh::regenerateAll(m, grids);
        benchmark::DoNotOptimize(grids.data());
    }
    state.counters["grid_nodes"] = static_cast<double>(m.gridNodeCount());
    state.SetItemsProcessed(state.iterations() * m.gridNodeCount());
}
BENCHMARK_CAPTURE(BM_Regenerate, paper, "paper")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Regenerate, coarse, "coarse")->Unit(benchmark::kMillisecond)->UseRealTime();

// Arg 0: the default solver (IC-preconditioned CG), a first move (its stiffness layout built and
// its memory touched for the first time); 1: the sparse Cholesky (CHOLMOD) of every increment;
// 2: the default solver with the MoveWorkspace of an earlier move of the same grid (the
// optimizer's evaluations and the editor's previews after the first); 3: the same, recording the
// move's history and keeping each increment's K and factor for the mesh adjoint
// (MoveWorkspace::setKeepIncrements, as the optimizer's evaluations run).
void BM_ControlGridMove(benchmark::State& state, const char* level) {
    const mesh::MultiBlockMesh base = mesh::extrudeToFarfield(geometry::makeHalfSphere(), mesh::extrusionLevel(level));
    mesh::MoveReport r;
    mesh::ElasticityOptions o;
    if (state.range(0) == 1) o.solver = mesh::ElasticityOptions::Solver::Direct;
    const std::vector<double>& surface = bwbSurface();  // the deformation itself is not timed
    mesh::MoveWorkspace kept;
    kept.setKeepIncrements(state.range(0) == 3);
    mesh::MoveHistory history;
    mesh::MoveHistory* recorded = state.range(0) == 3 ? &history : nullptr;
    const bool warm = state.range(0) >= 2;
    if (warm) {
        mesh::MultiBlockMesh m = base;
        mesh::moveControlGrid(m, surface, o, {}, nullptr, recorded, &kept);
    }
    for (auto _ : state) {
        mesh::MultiBlockMesh m = base;
        r = mesh::moveControlGrid(m, surface, o, {}, nullptr, recorded, warm ? &kept : nullptr);
        benchmark::DoNotOptimize(m.control.data());
    }
    state.counters["control_nodes"] = base.controlCount();
    state.counters["cg_iterations"] = r.totalIterations;
    state.counters["converged"] = r.status == mesh::SolveStatus::Converged;
    state.counters["direct_solves"] = r.directSolves;
}
BENCHMARK_CAPTURE(BM_ControlGridMove, paper, "paper")->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_ControlGridMove, coarse, "coarse")->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The mesh adjoint (issue #16): the move's six increments in reverse for `rhs` functionals at once,
// on the moved control grid of the blended-wing deformation; compare with BM_ControlGridMove (the
// forward move) in the same run. Second argument 1: with the forward move's MoveWorkspace; 2: and
// that move's K and factors kept (MoveWorkspace::setKeepIncrements, as the optimizer's gradient
// runs it).
void BM_MeshAdjoint(benchmark::State& state, const char* level) {
    const mesh::MultiBlockMesh base = mesh::extrudeToFarfield(geometry::makeHalfSphere(), mesh::extrusionLevel(level));
    mesh::MultiBlockMesh m = base;
    mesh::MoveHistory history;
    mesh::MoveWorkspace kept;
    kept.setKeepIncrements(state.range(1) == 2);
    const mesh::MoveReport r = mesh::moveControlGrid(m, bwbSurface(), mesh::ElasticityOptions{}, {}, nullptr, &history, &kept);
    const int rhs = static_cast<int>(state.range(0));
    std::vector<std::vector<double>> g(rhs, std::vector<double>(m.control.size()));
    for (int p = 0; p < rhs; ++p) {
        for (std::size_t i = 0; i < g[p].size(); ++i) g[p][i] = std::sin(0.37 * static_cast<double>(i) + p);
    }
    mesh::MeshAdjointReport rep;
    for (auto _ : state) {
        const auto gA = mesh::moveControlGridAdjoints(m, history, mesh::ElasticityOptions{}, g, &rep,
                                                      state.range(1) >= 1 ? &kept : nullptr);
        benchmark::DoNotOptimize(gA.data());
    }
    int its = 0;
    for (int i : rep.iterations) its += i;
    state.counters["control_nodes"] = base.controlCount();
    state.counters["cg_iterations"] = its;
    state.counters["forward_cg_iterations"] = r.totalIterations;
    state.counters["converged"] = rep.converged;
    state.counters["reused_increments"] = rep.reusedIncrements;
    state.counters["kept_mb"] = static_cast<double>(rep.keptBytes) / 1e6;
}
BENCHMARK_CAPTURE(BM_MeshAdjoint, coarse, "coarse")->Args({1, 0})->Args({2, 0})->Args({1, 1})->Args({1, 2})->Args({2, 2})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_MeshAdjoint, paper, "paper")->Args({1, 1})->Args({1, 2})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// N^T (the regeneration's transpose, for the grid sensitivities) against N in the same run.
void BM_RegenerateTranspose(benchmark::State& state, const char* level) {
    const mesh::MultiBlockMesh m = mesh::extrudeToFarfield(geometry::makeHalfSphere(), mesh::extrusionLevel(level));
    const auto grids = mesh::regenerateAll(m);
    std::vector<double> gb(m.control.size());
    for (auto _ : state) {
        std::fill(gb.begin(), gb.end(), 0.0);
        for (std::size_t b = 0; b < m.blocks.size(); ++b) mesh::regenerateTranspose(m, static_cast<int>(b), grids[b].xyz.data(), gb);
        benchmark::DoNotOptimize(gb.data());
    }
    state.SetItemsProcessed(state.iterations() * m.gridNodeCount());
}
BENCHMARK_CAPTURE(BM_RegenerateTranspose, coarse, "coarse")->Unit(benchmark::kMillisecond)->UseRealTime();

// The grid itself as an elasticity mesh: every grid node a node, every grid cell a hexahedron,
// coincident interface nodes merged; wall nodes follow the deformed surface.
struct NodeMesh {
    mesh::MultiBlockMesh mesh;
    std::vector<double> wall;  // target positions of the wall nodes (surfaceNode order)
};

NodeMesh nodeMesh(const char* level) {
    const auto set = geometry::makeHalfSphere();
    const mesh::MultiBlockMesh cm = mesh::extrudeToFarfield(set, mesh::extrusionLevel(level));
    const auto grids = mesh::regenerateAll(cm);
    // Target wall: the grid wall of the control grid moved by the same deformation (its wall layer
    // is the deformed geometry), i.e. the deformed surface sampled at the same parameters.
    mesh::MultiBlockMesh moved = cm;
    for (std::size_t u = 0; u < cm.surfaceNode.size(); ++u) {
        for (int c = 0; c < 3; ++c) moved.control[3 * cm.surfaceNode[u] + c] = bwbSurface()[3 * u + c];
    }
    const auto movedGrids = mesh::regenerateAll(moved);
    // Unique node numbering: union of coincident interface nodes.
    std::vector<long> offset(grids.size() + 1, 0);
    for (std::size_t b = 0; b < grids.size(); ++b) offset[b + 1] = offset[b] + grids[b].nodeCount();
    std::vector<long> parent(offset.back());
    std::iota(parent.begin(), parent.end(), 0L);
    auto find = [&](long x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& p : cm.interfaceNodes) parent[find(offset[p.blockA] + p.nodeA)] = find(offset[p.blockB] + p.nodeB);
    std::vector<int> id(parent.size(), -1);
    NodeMesh nm;
    int next = 0;
    for (long n = 0; n < static_cast<long>(parent.size()); ++n) {
        const long r = find(n);
        if (id[r] < 0) {
            id[r] = next++;
            nm.mesh.control.insert(nm.mesh.control.end(), {0, 0, 0});
        }
        id[n] = id[r];
    }
    std::vector<char> isWall(next, 0);
    for (std::size_t b = 0; b < grids.size(); ++b) {
        mesh::ControlBlock blk;
        blk.name = cm.blocks[b].name;
        blk.count = grids[b].dims;
        blk.faces = cm.blocks[b].faces;
        blk.nodes.resize(grids[b].nodeCount());
        for (long n = 0; n < grids[b].nodeCount(); ++n) {
            const int g = id[offset[b] + n];
            blk.nodes[n] = g;
            for (int c = 0; c < 3; ++c) nm.mesh.control[3 * g + c] = grids[b].xyz[3 * n + c];
        }
        for (int j = 0; j < grids[b].dims[1]; ++j) {
            for (int i = 0; i < grids[b].dims[0]; ++i) {
                const long n = grids[b].node(i, j, 0);
                const int g = id[offset[b] + n];
                if (!isWall[g]) {
                    isWall[g] = 1;
                    nm.mesh.surfaceNode.push_back(g);
                    nm.wall.insert(nm.wall.end(), &movedGrids[b].xyz[3 * n], &movedGrids[b].xyz[3 * n] + 3);
                }
            }
        }
        nm.mesh.blocks.push_back(std::move(blk));
    }
    return nm;
}

void BM_FineGridMove(benchmark::State& state, const char* level) {
    const NodeMesh base = nodeMesh(level);
    mesh::MoveReport r;
    for (auto _ : state) {
        mesh::MultiBlockMesh m = base.mesh;
        r = mesh::moveControlGrid(m, base.wall, mesh::ElasticityOptions{});
        benchmark::DoNotOptimize(m.control.data());
    }
    state.counters["nodes"] = base.mesh.controlCount();
    state.counters["cg_iterations"] = r.totalIterations;
    state.counters["converged"] = r.status == mesh::SolveStatus::Converged;
}
BENCHMARK_CAPTURE(BM_FineGridMove, coarse, "coarse")->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
