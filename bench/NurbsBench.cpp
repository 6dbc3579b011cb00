// NURBS kernel throughput. Run: build/release/bench/bench_nurbs
// Ratios matter more than absolute figures on a noisy 2-core machine: the sum-factorized
// structured sampling is compared with per-point evaluation of the same grid in the same run.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "nurbs/Inversion.h"
#include "nurbs/Surface.h"
#include "nurbs/Volume.h"

using namespace aero::nurbs;

namespace {

std::vector<double> clampedKnots(int p, int n) {
    std::vector<double> k(p + 1, 0.0);
    for (int i = 1; i < n - p; ++i) k.push_back(static_cast<double>(i) / (n - p));
    k.insert(k.end(), p + 1, 1.0);
    return k;
}

// A cubic volume with a 20x20x18 control net, smoothly perturbed (like a mesh block's).
Volume<double> makeVolume(bool rational) {
    Volume<double> v;
    v.degree = {3, 3, 3};
    v.count = {20, 20, 18};
    for (int d = 0; d < 3; ++d) v.knots[d] = clampedKnots(3, v.count[d]);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(-0.01, 0.01);
    for (int k = 0; k < v.count[2]; ++k) {
        for (int j = 0; j < v.count[1]; ++j) {
            for (int i = 0; i < v.count[0]; ++i) {
                v.points.insert(v.points.end(), {i + U(rng), j + U(rng), k + U(rng)});
            }
        }
    }
    if (rational) v.weights.assign(v.controlCount(), 1.0), v.weights[123] = 1.5;
    return v;
}

std::vector<double> linspace(int n) {
    std::vector<double> s(n);
    for (int i = 0; i < n; ++i) s[i] = static_cast<double>(i) / (n - 1);
    return s;
}

void BM_VolumeSampleGrid(benchmark::State& state) {
    const Volume<double> v = makeVolume(state.range(0) != 0);
    const auto s0 = linspace(100), s1 = linspace(100), s2 = linspace(90);
    std::vector<double> out(3 * s0.size() * s1.size() * s2.size());
    for (auto _ : state) {
        sampleGrid(v, s0, s1, s2, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * 100 * 100 * 90);
}
BENCHMARK(BM_VolumeSampleGrid)->Arg(0)->Arg(1)->ArgNames({"rational"})->Unit(benchmark::kMillisecond)->UseRealTime();

// The same 100x100x90 grid by per-point de Boor evaluation (the batched point API).
void BM_VolumePointwiseGrid(benchmark::State& state) {
    const Volume<double> v = makeVolume(false);
    const auto s0 = linspace(100), s1 = linspace(100), s2 = linspace(90);
    std::vector<double> params;
    for (double z : s2) {
        for (double y : s1) {
            for (double x : s0) params.insert(params.end(), {x, y, z});
        }
    }
    std::vector<double> out(params.size());
    for (auto _ : state) {
        evaluate(v, params, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * 100 * 100 * 90);
}
BENCHMARK(BM_VolumePointwiseGrid)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SurfaceSampleGrid(benchmark::State& state) {
    Surface<double> s;
    s.degreeU = s.degreeV = 3;
    s.countU = s.countV = 20;
    s.knotsU = s.knotsV = clampedKnots(3, 20);
    for (int j = 0; j < 20; ++j) {
        for (int i = 0; i < 20; ++i) s.points.insert(s.points.end(), {double(i), double(j), 0.1 * (i * j % 7)});
    }
    const auto us = linspace(316), vs = linspace(316);
    std::vector<double> out(3 * us.size() * vs.size());
    for (auto _ : state) {
        sampleGrid(s, us, vs, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * 316 * 316);
}
BENCHMARK(BM_SurfaceSampleGrid)->Unit(benchmark::kMillisecond)->UseRealTime();

// Volume point inversion (the FFD embedding F^-1) of random interior points.
void BM_VolumeInversion(benchmark::State& state) {
    Volume<double> v;
    v.degree = {3, 3, 1};
    v.count = {6, 6, 2};
    for (int d = 0; d < 3; ++d) v.knots[d] = clampedKnots(v.degree[d], v.count[d]);
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 6; ++j) {
            for (int i = 0; i < 6; ++i) v.points.insert(v.points.end(), {0.4 * i + 0.02 * j * j, 0.5 * j, 1.0 * k + 0.03 * i});
        }
    }
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> D(0.0, 1.0);
    const int n = static_cast<int>(state.range(0));
    std::vector<double> pts;
    for (int t = 0; t < n; ++t) {
        const Vec3<double> P = evaluate(v, D(rng), D(rng), D(rng));
        pts.insert(pts.end(), {P[0], P[1], P[2]});
    }
    std::vector<VolumeInversion> out(n);
    for (auto _ : state) {
        const VolumeInverter inv(v);
        inv.invertAll(pts, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * n);
}
BENCHMARK(BM_VolumeInversion)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
