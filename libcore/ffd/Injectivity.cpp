#include "ffd/Injectivity.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

#include "nurbs/KnotInsertion.h"

namespace aero::ffd {

using nurbs::Vec3;

namespace {

double detJ(const Lattice& v, double a, double b, double c) {
    Vec3<double> P;
    Eigen::Matrix3d J;
    nurbs::evaluateJacobian(v, a, b, c, P, J);
    return J.determinant();
}

Vec3<double> point(const Lattice& v, int i, int j, int k) {
    const int a = v.index(i, j, k);
    return Vec3<double>(v.points[3 * a], v.points[3 * a + 1], v.points[3 * a + 2]);
}

// Returns true if every knot cell passes the triple-product test with sign `sign`; otherwise
// stores the centre of the first failing cell.
bool certify(const Lattice& v, double sign, std::array<double, 3>& failedCell) {
    const int p0 = v.degree[0], p1 = v.degree[1], p2 = v.degree[2];
    std::vector<Vec3<double>> D0, D1, D2, cross12;
    for (int s2 = p2; s2 < v.count[2]; ++s2) {
        if (!(v.knots[2][s2 + 1] > v.knots[2][s2])) continue;
        for (int s1 = p1; s1 < v.count[1]; ++s1) {
            if (!(v.knots[1][s1 + 1] > v.knots[1][s1])) continue;
            for (int s0 = p0; s0 < v.count[0]; ++s0) {
                if (!(v.knots[0][s0 + 1] > v.knots[0][s0])) continue;
                // Differences active on this cell (positive scale factors dropped: signs only).
                D0.clear();
                D1.clear();
                D2.clear();
                for (int k = s2 - p2; k <= s2; ++k) {
                    for (int j = s1 - p1; j <= s1; ++j) {
                        for (int i = s0 - p0; i <= s0; ++i) {
                            if (i < s0) D0.push_back(point(v, i + 1, j, k) - point(v, i, j, k));
                            if (j < s1) D1.push_back(point(v, i, j + 1, k) - point(v, i, j, k));
                            if (k < s2) D2.push_back(point(v, i, j, k + 1) - point(v, i, j, k));
                        }
                    }
                }
                cross12.clear();
                for (const auto& b : D1) {
                    for (const auto& c : D2) cross12.push_back(b.cross(c));
                }
                for (const auto& a : D0) {
                    for (const auto& bc : cross12) {
                        if (!(sign * a.dot(bc) > 0.0)) {
                            failedCell = {0.5 * (v.knots[0][s0] + v.knots[0][s0 + 1]),
                                          0.5 * (v.knots[1][s1] + v.knots[1][s1 + 1]),
                                          0.5 * (v.knots[2][s2] + v.knots[2][s2 + 1])};
                            return false;
                        }
                    }
                }
            }
        }
    }
    return true;
}

// Midpoints of every non-empty knot span of one direction.
std::vector<double> spanMidpoints(const std::vector<double>& U) {
    std::vector<double> m;
    for (std::size_t i = 0; i + 1 < U.size(); ++i) {
        if (U[i + 1] > U[i]) m.push_back(0.5 * (U[i] + U[i + 1]));
    }
    return m;
}

}  // namespace

InjectivityReport checkInjectivity(const Lattice& lattice, const InjectivityOptions& o) {
    InjectivityReport r;
    std::array<std::vector<double>, 3> s;
    for (int d = 0; d < 3; ++d) {
        const auto& U = lattice.knots[d];
        for (std::size_t i = 0; i + 1 < U.size(); ++i) {
            if (!(U[i + 1] > U[i])) continue;
            for (int t = 0; t < o.samplesPerSpan; ++t) s[d].push_back(U[i] + (U[i + 1] - U[i]) * t / o.samplesPerSpan);
        }
        s[d].push_back(U.back());
    }
    std::vector<double> dets;
    dets.reserve(s[0].size() * s[1].size() * s[2].size());
    double total = 0;
    for (double c : s[2]) {
        for (double b : s[1]) {
            for (double a : s[0]) {
                dets.push_back(detJ(lattice, a, b, c));
                total += dets.back();
            }
        }
    }
    // Orientation: the sign of the image volume (sum of sampled det J), so a fold through the
    // centre does not flip the verdict. The sampled minimum of sign * det J follows.
    const double sign = total < 0 ? -1.0 : 1.0;
    const double mean = std::abs(total) / static_cast<double>(dets.size());
    r.minJacobian = std::numeric_limits<double>::infinity();
    std::size_t t = 0;
    for (double c : s[2]) {
        for (double b : s[1]) {
            for (double a : s[0]) {
                const double dj = sign * dets[t++];
                if (dj < r.minJacobian) {
                    r.minJacobian = dj;
                    r.minAt = {a, b, c};
                }
            }
        }
    }
    const Vec3<double> mp = nurbs::evaluate(lattice, r.minAt[0], r.minAt[1], r.minAt[2]);
    r.minPoint = {mp[0], mp[1], mp[2]};
    r.relativeMinJacobian = mean > 0 ? r.minJacobian / mean : -1.0;
    if (!(mean > 0) || !std::isfinite(mean) || !(r.minJacobian > 0)) {
        r.failedCell = r.minAt;
        return r;  // det J vanishes or changes sign at a sample: certainly not injective
    }
    if (lattice.rational()) {
        r.injective = true;  // sampled only: the triple-product certificate is for polynomial maps
        return r;
    }
    Lattice refined = lattice;
    for (r.refinements = 0; r.refinements <= o.maxRefinements; ++r.refinements) {
        if (certify(refined, sign, r.failedCell)) {
            r.certified = r.injective = true;
            return r;
        }
        if (r.refinements == o.maxRefinements) break;
        for (int d = 0; d < 3; ++d) nurbs::refine(refined, d, spanMidpoints(refined.knots[d]));
    }
    return r;
}

}  // namespace aero::ffd
