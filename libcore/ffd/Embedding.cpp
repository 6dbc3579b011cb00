#include "ffd/Embedding.h"

#include <algorithm>
#include <chrono>

#include "common/Error.h"

namespace aero::ffd {

Embedding embed(const geometry::PatchSet& set, const Lattice& lattice, const std::vector<int>& patches,
                const EmbeddingOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    Embedding e;
    e.index = geometry::buildControlPointIndex(set, 1e-10);
    // Which unique points to embed (and the first patch holding each, for messages).
    std::vector<int> firstPatch(e.index.uniqueCount(), -1);
    std::vector<bool> wanted(e.index.uniqueCount(), patches.empty());
    for (int p = 0; p < set.size(); ++p) {
        const bool selected = patches.empty() || std::find(patches.begin(), patches.end(), p) != patches.end();
        for (int a = e.index.patchOffset[p]; a < e.index.patchOffset[p + 1]; ++a) {
            const int u = e.index.toUnique[a];
            if (firstPatch[u] < 0) firstPatch[u] = p;
            if (selected) wanted[u] = true;
        }
    }
    std::vector<int> candidates;
    std::vector<double> xyz;
    for (int u = 0; u < e.index.uniqueCount(); ++u) {
        if (!wanted[u]) continue;
        candidates.push_back(u);
        xyz.insert(xyz.end(), &e.index.points[3 * u], &e.index.points[3 * u] + 3);
    }
    nurbs::InversionOptions io;
    io.tolerance = o.tolerance;
    io.maxIterations = o.maxIterations;
    const nurbs::VolumeInverter inverter(lattice, io);
    std::vector<nurbs::VolumeInversion> inv(candidates.size());
    inverter.invertAll(xyz, inv.data());
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        const nurbs::VolumeInversion& r = inv[c];
        e.iterationsMax = std::max(e.iterationsMax, r.iterations);
        if (r.converged) {
            e.points.push_back(candidates[c]);
            e.params.insert(e.params.end(), r.xi.begin(), r.xi.end());
            e.maxError = std::max(e.maxError, r.residual);
        } else {
            e.failures.push_back({candidates[c], firstPatch[candidates[c]], r.residual, !r.inside});
        }
    }
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return e;
}

void deformUnique(const Lattice& lattice, const Embedding& e, std::vector<double>& unique) {
    std::vector<double> out(e.params.size());
    nurbs::evaluate(lattice, e.params, out.data());
    for (std::size_t p = 0; p < e.points.size(); ++p) {
        for (int c = 0; c < 3; ++c) unique[3 * e.points[p] + c] = out[3 * p + c];
    }
}

void scatter(const geometry::ControlPointIndex& index, const std::vector<double>& unique, geometry::PatchSet& set) {
    for (int p = 0; p < set.size(); ++p) {
        auto& pts = set.patches[p].points;
        for (int a = index.patchOffset[p]; a < index.patchOffset[p + 1]; ++a) {
            const int u = index.toUnique[a];
            const int local = a - index.patchOffset[p];
            for (int c = 0; c < 3; ++c) pts[3 * local + c] = unique[3 * u + c];
        }
    }
}

Eigen::SparseMatrix<double, Eigen::RowMajor> sensitivity(const Lattice& lattice, const Embedding& e) {
    const int n = static_cast<int>(e.points.size());
    const int per = (lattice.degree[0] + 1) * (lattice.degree[1] + 1) * (lattice.degree[2] + 1);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(n) * per);
    std::vector<int> idx(per);
    std::vector<double> val(per);
    for (int p = 0; p < n; ++p) {
        const int m = nurbs::basisAt(lattice, &e.params[3 * p], idx.data(), val.data());
        for (int t = 0; t < m; ++t) {
            if (val[t] != 0.0) triplets.emplace_back(p, idx[t], val[t]);
        }
    }
    Eigen::SparseMatrix<double, Eigen::RowMajor> W(n, lattice.controlCount());
    W.setFromTriplets(triplets.begin(), triplets.end());
    return W;
}

}  // namespace aero::ffd
