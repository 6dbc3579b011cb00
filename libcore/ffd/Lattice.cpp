#include "ffd/Lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/Error.h"
#include "nurbs/Basis.h"
#include "nurbs/KnotInsertion.h"

namespace aero::ffd {

Lattice makeLattice(const LatticeBox& box, std::array<int, 3> count, std::array<int, 3> degree) {
    for (int d = 0; d < 3; ++d) {
        if (degree[d] < 1 || degree[d] > nurbs::kMaxDegree || count[d] < degree[d] + 1) {
            throw GeometryError("FFD lattice: direction " + std::to_string(d) + " has " + std::to_string(count[d]) +
                                " control points for degree " + std::to_string(degree[d]) +
                                " (need degree in [1, 9] and at least degree + 1 points)");
        }
        if (!(box.size[d] > 0) || !std::isfinite(box.size[d])) {
            throw GeometryError("FFD lattice: box size " + std::to_string(box.size[d]) + " in direction " +
                                std::to_string(d) + " must be positive");
        }
    }
    Lattice v;
    v.degree = degree;
    v.count = count;
    std::array<std::vector<double>, 3> greville;
    for (int d = 0; d < 3; ++d) {
        v.knots[d] = nurbs::uniformKnots(degree[d], count[d]);
        greville[d].resize(count[d]);
        for (int i = 0; i < count[d]; ++i) {
            double s = 0;
            for (int m = 1; m <= degree[d]; ++m) s += v.knots[d][i + m];
            greville[d][i] = s / degree[d];
        }
    }
    v.points.resize(3 * static_cast<std::size_t>(v.controlCount()));
    for (int k = 0; k < count[2]; ++k) {
        for (int j = 0; j < count[1]; ++j) {
            for (int i = 0; i < count[0]; ++i) {
                const double t[3] = {greville[0][i] * box.size[0], greville[1][j] * box.size[1],
                                     greville[2][k] * box.size[2]};
                const int a = v.index(i, j, k);
                for (int c = 0; c < 3; ++c) {
                    v.points[3 * a + c] =
                        box.origin[c] + t[0] * box.axes[0][c] + t[1] * box.axes[1][c] + t[2] * box.axes[2][c];
                }
            }
        }
    }
    return v;
}

LatticeBox boxAround(const geometry::PatchSet& set, const std::vector<int>& patches, std::array<double, 3> padding,
                     const std::array<std::array<double, 3>, 3>& axes) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    auto include = [&](const geometry::Patch& p) {
        for (std::size_t a = 0; a < p.points.size(); a += 3) {
            for (int d = 0; d < 3; ++d) {
                const double t = p.points[a] * axes[d][0] + p.points[a + 1] * axes[d][1] + p.points[a + 2] * axes[d][2];
                lo[d] = std::min(lo[d], t);
                hi[d] = std::max(hi[d], t);
            }
        }
    };
    if (patches.empty()) {
        for (const auto& p : set.patches) include(p);
    } else {
        for (int i : patches) {
            if (i < 0 || i >= set.size()) {
                throw GeometryError("FFD lattice: patch index " + std::to_string(i) + " is outside [0, " +
                                    std::to_string(set.size() - 1) + "] of '" + set.source + "'");
            }
            include(set.patches[i]);
        }
    }
    if (!(lo[0] <= hi[0])) throw GeometryError("FFD lattice: no control points to enclose");
    const double largest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    LatticeBox box;
    box.axes = axes;
    double origin[3];
    for (int d = 0; d < 3; ++d) {
        const double extent = hi[d] - lo[d];
        const double pad = extent > 1e-9 * largest ? padding[d] * extent : 1e-3 * largest;
        origin[d] = lo[d] - pad;
        box.size[d] = (hi[d] - lo[d]) + 2 * pad;
    }
    for (int c = 0; c < 3; ++c) {
        box.origin[c] = origin[0] * axes[0][c] + origin[1] * axes[1][c] + origin[2] * axes[2][c];
    }
    return box;
}

void refineLattice(Lattice& lattice, int dir, std::span<const double> knots) { nurbs::refine(lattice, dir, knots); }

void creaseLattice(Lattice& lattice, int dir, double u) {
    const int have = nurbs::multiplicity(lattice.knots[dir], u);
    if (have < lattice.degree[dir]) nurbs::insertKnot(lattice, dir, u, lattice.degree[dir] - have);
}

}  // namespace aero::ffd
