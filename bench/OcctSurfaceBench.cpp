// Surface evaluation throughput: our batched aero::nurbs::evaluate against OpenCASCADE's
// Geom_BSplineSurface::D0 called point by point, on the same bicubic 20x20 surface
// (non-uniform knots) and the same 100,000 random (u, v) points; polynomial and rational.
// Our batched call runs OpenMP over points (all threads, then one: the per-core comparison);
// OCCT runs on one thread.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Pnt.hxx>
#include <random>
#include <vector>

#include "nurbs/Surface.h"

namespace {

using aero::nurbs::Surface;

constexpr int kDegree = 3;
constexpr int kCount = 20;
constexpr int kPoints = 100000;

/// Clamped knots on [0, 1] with random interior spacing (interior knots simple).
std::vector<double> nonUniformKnots(std::mt19937& rng) {
    std::uniform_real_distribution<double> gap(0.5, 1.5);
    std::vector<double> interior(kCount - kDegree - 1);
    double sum = 0;
    for (double& k : interior) k = (sum += gap(rng));
    sum += gap(rng);
    std::vector<double> knots(kDegree + 1, 0.0);
    for (double k : interior) knots.push_back(k / sum);
    knots.insert(knots.end(), kDegree + 1, 1.0);
    return knots;
}

Surface<double> makeSurface(bool rational) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> bump(-0.2, 0.2), weight(0.5, 2.0);
    Surface<double> s;
    s.degreeU = s.degreeV = kDegree;
    s.countU = s.countV = kCount;
    s.knotsU = nonUniformKnots(rng);
    s.knotsV = nonUniformKnots(rng);
    for (int j = 0; j < kCount; ++j)
        for (int i = 0; i < kCount; ++i) {
            s.points.push_back(i / double(kCount - 1));
            s.points.push_back(j / double(kCount - 1));
            s.points.push_back(bump(rng));
            if (rational) s.weights.push_back(weight(rng));
        }
    return s;
}

Handle(Geom_BSplineSurface) toOcct(const Surface<double>& s) {
    auto compress = [](const std::vector<double>& flat, TColStd_Array1OfReal& knots,
                       TColStd_Array1OfInteger& mults) {
        std::vector<double> distinct;
        std::vector<int> count;
        for (double k : flat) {
            if (distinct.empty() || k != distinct.back()) {
                distinct.push_back(k);
                count.push_back(0);
            }
            ++count.back();
        }
        const int n = static_cast<int>(distinct.size());
        knots.Resize(1, n, Standard_False);
        mults.Resize(1, n, Standard_False);
        for (int i = 0; i < n; ++i) {
            knots(i + 1) = distinct[i];
            mults(i + 1) = count[i];
        }
    };
    TColStd_Array1OfReal ku(1, 1), kv(1, 1);
    TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
    compress(s.knotsU, ku, mu);
    compress(s.knotsV, kv, mv);
    TColgp_Array2OfPnt poles(1, s.countU, 1, s.countV);
    TColStd_Array2OfReal weights(1, s.countU, 1, s.countV);
    for (int j = 0; j < s.countV; ++j)
        for (int i = 0; i < s.countU; ++i) {
            const int k = s.index(i, j);
            poles(i + 1, j + 1) = gp_Pnt(s.points[3 * k], s.points[3 * k + 1], s.points[3 * k + 2]);
            weights(i + 1, j + 1) = s.rational() ? s.weights[k] : 1.0;
        }
    if (s.rational())
        return new Geom_BSplineSurface(poles, weights, ku, kv, mu, mv, kDegree, kDegree);
    return new Geom_BSplineSurface(poles, ku, kv, mu, mv, kDegree, kDegree);
}

const std::vector<double>& randomParameters() {
    static const std::vector<double> uv = [] {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        std::vector<double> p(2 * kPoints);
        for (double& x : p) x = U(rng);
        return p;
    }();
    return uv;
}

/// state.range(0): 0 polynomial, 1 rational; state.range(1): OpenMP threads.
void BM_OursBatched(benchmark::State& state) {
    const Surface<double> s = makeSurface(state.range(0) == 1);
    const std::vector<double>& uv = randomParameters();
    std::vector<double> out(3 * kPoints);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(static_cast<int>(state.range(1)));
    for (auto _ : state) {
        aero::nurbs::evaluate(s, uv, out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    omp_set_num_threads(threads);
    state.SetItemsProcessed(state.iterations() * kPoints);
}

void BM_OcctD0(benchmark::State& state) {
    const Handle(Geom_BSplineSurface) surface = toOcct(makeSurface(state.range(0) == 1));
    const std::vector<double>& uv = randomParameters();
    std::vector<double> out(3 * kPoints);
    for (auto _ : state) {
        gp_Pnt p;
        for (int i = 0; i < kPoints; ++i) {
            surface->D0(uv[2 * i], uv[2 * i + 1], p);
            out[3 * i] = p.X();
            out[3 * i + 1] = p.Y();
            out[3 * i + 2] = p.Z();
        }
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * kPoints);
}

BENCHMARK(BM_OursBatched)
    ->ArgNames({"rational", "threads"})
    ->ArgsProduct({{0, 1}, {omp_get_max_threads(), 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_OcctD0)
    ->ArgNames({"rational"})
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
