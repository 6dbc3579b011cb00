// First-level FFD throughput. Run: build/release/bench/bench_ffd
#include <benchmark/benchmark.h>

#include <random>

#include "ffd/FfdModel.h"
#include "ffd/Injectivity.h"
#include "geometry/HalfSphere.h"

using namespace aero;
using namespace aero::ffd;

namespace {

// A cubic 8x8x8 lattice over a gently sheared box, and 100,000 random interior points.
struct Setup {
    Lattice lattice;
    std::vector<double> points;
    Setup() {
        LatticeBox box;
        box.size = {2.0, 1.5, 1.0};
        lattice = makeLattice(box, {8, 8, 8}, {3, 3, 3});
        for (int a = 0; a < lattice.controlCount(); ++a) {
            const double x = lattice.points[3 * a], y = lattice.points[3 * a + 1];
            lattice.points[3 * a + 2] += 0.1 * std::sin(2 * x) * y;
        }
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        for (int t = 0; t < 100000; ++t) {
            const auto P = nurbs::evaluate(lattice, U(rng), U(rng), U(rng));
            points.insert(points.end(), {P[0], P[1], P[2]});
        }
    }
};

const Setup& setup() {
    static const Setup s;
    return s;
}

// The 100,000 points embedded once (for the deformation and sensitivity benchmarks).
Embedding embedAll(const Setup& s) {
    Embedding e;
    e.points.resize(100000);
    for (int i = 0; i < 100000; ++i) e.points[i] = i;
    const nurbs::VolumeInverter inv(s.lattice);
    std::vector<nurbs::VolumeInversion> r(100000);
    inv.invertAll(s.points, r.data());
    for (const auto& x : r) e.params.insert(e.params.end(), x.xi.begin(), x.xi.end());
    return e;
}

void BM_Embed100k(benchmark::State& state) {
    const Setup& s = setup();
    std::vector<nurbs::VolumeInversion> out(s.points.size() / 3);
    for (auto _ : state) {
        const nurbs::VolumeInverter inv(s.lattice);
        inv.invertAll(s.points, out.data());
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * 100000);
}
BENCHMARK(BM_Embed100k)->Unit(benchmark::kMillisecond)->UseRealTime();

// Deformation F~ of 100,000 embedded points, and the dA/dB sparse assembly (Eq. 3).
void BM_Deform100k(benchmark::State& state) {
    const Setup& s = setup();
    const Embedding e = embedAll(s);
    std::vector<double> A(s.points.size());
    for (auto _ : state) {
        deformUnique(s.lattice, e, A);
        benchmark::DoNotOptimize(A.data());
    }
    state.SetItemsProcessed(state.iterations() * 100000);
}
BENCHMARK(BM_Deform100k)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Sensitivity100k(benchmark::State& state) {
    const Setup& s = setup();
    const Embedding e = embedAll(s);
    for (auto _ : state) {
        const auto W = sensitivity(s.lattice, e);
        benchmark::DoNotOptimize(W.nonZeros());
    }
    state.SetItemsProcessed(state.iterations() * 100000);
}
BENCHMARK(BM_Sensitivity100k)->Unit(benchmark::kMillisecond)->UseRealTime();

// The paper's sample: 89 design variables on the half-sphere.
FfdModel paperModel() {
    const auto set = geometry::makeHalfSphere();
    LatticeSpec spec;
    spec.lattice = makeLattice(boxAround(set, {}, {0.05, 0.0, 0.05}), {6, 6, 2}, {3, 3, 1});
    FfdModel m(set, {spec});
    StationSpec st;
    st.bits = {"001", "011", "011", "011", "011", "011"};
    m.design().addStations(st);
    return m;
}

void BM_HalfSphereDeform(benchmark::State& state) {
    const FfdModel m = paperModel();
    const auto v = m.design().baselineValues();
    for (auto _ : state) benchmark::DoNotOptimize(m.deform(v).patches.data());
}
BENCHMARK(BM_HalfSphereDeform)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_HalfSphereDADv(benchmark::State& state) {
    const FfdModel m = paperModel();
    for (auto _ : state) benchmark::DoNotOptimize(m.dUniqueDv().nonZeros());
}
BENCHMARK(BM_HalfSphereDADv)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_HalfSphereVolumeGradient(benchmark::State& state) {
    const FfdModel m = paperModel();
    const auto v = m.design().baselineValues();
    for (auto _ : state) benchmark::DoNotOptimize(m.volumeGradient(v).data());
}
BENCHMARK(BM_HalfSphereVolumeGradient)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_Injectivity6x6x2(benchmark::State& state) {
    const FfdModel m = paperModel();
    for (auto _ : state) benchmark::DoNotOptimize(checkInjectivity(m.lattices()[0].lattice).minJacobian);
}
BENCHMARK(BM_Injectivity6x6x2)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
