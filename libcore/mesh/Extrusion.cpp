#include "mesh/Extrusion.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/Error.h"
#include "geometry/Topology.h"
#include "nurbs/Basis.h"

namespace aero::mesh {

ExtrusionOptions extrusionLevel(const std::string& name) {
    ExtrusionOptions o;
    if (name == "coarse") return o;
    if (name == "medium") {
        o.gridWallSpacing = 1e-3;
        o.radialControlPoints = 18;
        o.surfaceNodes = 23;
        o.radialNodes = 29;
        return o;
    }
    if (name == "paper") {
        o.gridWallSpacing = 1e-3;
        o.radialControlPoints = 26;
        o.surfaceNodes = 31;
        o.radialNodes = 47;
        return o;
    }
    throw CaseError("mesh.level: unknown level '" + name + "' (expected coarse, medium or paper)");
}

namespace {

// Geometric distribution: n - 1 intervals from 0 to 1 with first interval `first`.
std::vector<double> geometricLayers(int n, double first) {
    std::vector<double> t(n);
    const int m = n - 1;
    double lo = 1.0, hi = 10.0;  // growth ratio q with first * (q^m - 1)/(q - 1) = 1
    auto total = [&](double q) {
        return std::abs(q - 1) < 1e-12 ? first * m : first * (std::pow(q, m) - 1) / (q - 1);
    };
    if (total(1.0) >= 1.0) {
        for (int k = 0; k < n; ++k) t[k] = static_cast<double>(k) / m;
        return t;
    }
    while (total(hi) < 1.0) hi *= 2;
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (total(mid) < 1.0 ? lo : hi) = mid;
    }
    const double q = 0.5 * (lo + hi);
    double s = 0, d = first;
    for (int k = 0; k < n; ++k) {
        t[k] = s;
        s += d;
        d *= q;
    }
    t[m] = 1.0;
    return t;
}

// Radial grid parameters whose physical spacing grows smoothly. Every column's control nodes lie
// on its straight line at the fractions t_k of its length, so the fraction of the column at
// parameter zeta is one monotone cubic s(zeta) = sum_k N_k(zeta) t_k for all columns. The grid's
// fractions follow sigma(t) = (exp(beta t) - 1) / (exp(beta) - 1) at uniform t, beta chosen so
// the first of the base level's intervals is `first` (a constant ratio exp(beta / n) between
// neighbouring spacings), and zeta = s^-1(sigma). Refinement samples the same sigma more densely
// (a true refinement of one analytic grid: node 2i of a twice finer grid is node i).
// Sampling zeta itself with such a law (the former rule) multiplied two exponentials: the
// coarse level's last radial cell was 18.5 times its neighbour.
std::vector<double> radialSamples(const std::vector<double>& knots, int degree, const std::vector<double>& t,
                                  int baseIntervals, double first, double refine) {
    auto sigma = [](double beta, double x) {
        return beta < 1e-9 ? x : std::expm1(beta * x) / std::expm1(beta);
    };
    const double t1 = 1.0 / baseIntervals;
    double beta = 0;
    if (first < t1) {
        double lo = 1e-9, hi = 1.0;
        while (sigma(hi, t1) > first) hi *= 2;
        for (int it = 0; it < 200; ++it) {
            const double mid = 0.5 * (lo + hi);
            (sigma(mid, t1) > first ? lo : hi) = mid;
        }
        beta = 0.5 * (lo + hi);
    }
    const int count = static_cast<int>(t.size());
    auto fraction = [&](double zeta) {
        const int span = nurbs::findSpan(knots, degree, count, zeta);
        double N[nurbs::kMaxDegree + 1];
        nurbs::basisFunctions(knots, degree, span, zeta, N);
        double v = 0;
        for (int a = 0; a <= degree; ++a) v += N[a] * t[span - degree + a];
        return v;
    };
    const int n = std::max(1, static_cast<int>(std::lround(baseIntervals * refine)));
    std::vector<double> s(n + 1);
    s[0] = 0.0;
    s[n] = 1.0;
    for (int i = 1; i < n; ++i) {
        const double target = sigma(beta, static_cast<double>(i) / n);
        double lo = 0.0, hi = 1.0;  // s is monotone (increasing control fractions)
        for (int it = 0; it < 100; ++it) {
            const double mid = 0.5 * (lo + hi);
            (fraction(mid) < target ? lo : hi) = mid;
        }
        s[i] = 0.5 * (lo + hi);
    }
    return s;
}

std::vector<double> uniformSamples(int baseIntervals, double refine) {
    const int n = std::max(1, static_cast<int>(std::lround(baseIntervals * refine)));
    std::vector<double> s(n + 1);
    for (int i = 0; i <= n; ++i) s[i] = (i == n) ? 1.0 : static_cast<double>(i) / n;
    return s;
}

// Patch edge -> block face: edge 0 (v = v0) is j = 0, 1 (u = u1) is i = max, 2 is j = max, 3 is i =
// 0.
constexpr int kEdgeFace[4] = {static_cast<int>(Face::JMin), static_cast<int>(Face::IMax),
                              static_cast<int>(Face::JMax), static_cast<int>(Face::IMin)};

}  // namespace

MultiBlockMesh extrudeToFarfield(const geometry::PatchSet& set, const ExtrusionOptions& o) {
    // Each block is a whole patch's control net extruded outwards: a trimmed patch's net covers
    // more than its trimmed surface, so the grid's wall would not be the body.
    geometry::requireUntrimmed(set, "mesh generation (extrusion of whole patch nets)");
    if (o.radialControlPoints < o.radialDegree + 1 || o.radialDegree < 1 || o.surfaceNodes < 2 ||
        o.radialNodes < 2 || !(o.refine > 0) || !(o.farfieldRadius > 1) ||
        !(o.controlWallSpacing > 0) || !(o.gridWallSpacing > 0)) {
        throw CaseError(
            "mesh: invalid extrusion options (radial control points >= degree + 1, nodes >= 2, "
            "positive "
            "spacings and refinement, farfield radius > 1 body radius)");
    }
    // Refuse hostile sizes before allocating (issue #20): a grid of kMaxGridNodes takes about
    // 7 KB per node in a flow solve.
    {
        const double along = std::max(1.0, std::round((o.surfaceNodes - 1) * o.refine)) + 1;
        const double radial = std::max(1.0, std::round((o.radialNodes - 1) * o.refine)) + 1;
        const double nodes = static_cast<double>(set.size()) * along * along * radial;
        if (nodes > kMaxGridNodes) {
            char b[400];
            std::snprintf(b, sizeof b,
                          "mesh: the grid would have %.3g nodes (%d blocks of %.0f x %.0f x %.0f: surface_nodes %d, "
                          "radial_nodes %d, refine %g), more than the %.0f million accepted (a flow solve needs about "
                          "7 KB per node); lower mesh.refine or the node counts",
                          nodes, set.size(), along, along, radial, o.surfaceNodes, o.radialNodes, o.refine,
                          kMaxGridNodes / 1e6);
            throw CaseError(b);
        }
        double wall = 0;
        for (const auto& patch : set.patches) wall += static_cast<double>(patch.countU) * patch.countV;
        const double control = wall * o.radialControlPoints;
        if (control > kMaxControlNodes) {
            throw CaseError("mesh: radial_control_points " + std::to_string(o.radialControlPoints) +
                            " would give about " + std::to_string(static_cast<long>(control)) +
                            " control nodes, more than the " + std::to_string(static_cast<long>(kMaxControlNodes)) +
                            " the elasticity solve accepts");
        }
    }
    geometry::validate(set);
    const geometry::ControlPointIndex idx = geometry::buildControlPointIndex(set, 1e-10);
    const int nu = idx.uniqueCount(), nk = o.radialControlPoints;
    // Body centre on the symmetry plane, body radius.
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int u = 0; u < nu; ++u) {
        for (int c = 0; c < 3; ++c) {
            lo[c] = std::min(lo[c], idx.points[3 * u + c]);
            hi[c] = std::max(hi[c], idx.points[3 * u + c]);
        }
    }
    const double centre[3] = {0.5 * (lo[0] + hi[0]), 0.0, 0.5 * (lo[2] + hi[2])};
    double radius = 0;
    for (int u = 0; u < nu; ++u) {
        double r2 = 0;
        for (int c = 0; c < 3; ++c)
            r2 += (idx.points[3 * u + c] - centre[c]) * (idx.points[3 * u + c] - centre[c]);
        radius = std::max(radius, std::sqrt(r2));
    }
    const double farfield = o.farfieldRadius * radius;

    MultiBlockMesh m;
    m.control.resize(3 * static_cast<std::size_t>(nu) * nk);
    m.surfaceNode.resize(nu);
    for (int u = 0; u < nu; ++u) {
        const double* p = &idx.points[3 * u];
        double dir[3], r0 = 0;
        for (int c = 0; c < 3; ++c) {
            dir[c] = p[c] - centre[c];
            r0 += dir[c] * dir[c];
        }
        r0 = std::sqrt(r0);
        if (!(r0 > 1e-6 * radius)) {
            throw GeometryError("mesh: control point (" + std::to_string(p[0]) + ", " +
                                std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                                ") coincides with the body centre: the body is not star-shaped");
        }
        for (double& d : dir) d /= r0;
        if (std::abs(p[1]) <= o.symmetryTolerance) dir[1] = 0.0;  // columns on the plane stay on it
        const std::vector<double> t =
            geometricLayers(nk, o.controlWallSpacing * radius / (farfield - r0));
        m.surfaceNode[u] = u;  // k = 0 layer: global node u is the geometry control point u
        for (int k = 0; k < nk; ++k) {
            const int g = u + nu * k;
            for (int c = 0; c < 3; ++c) {
                const double wall = p[c], far = centre[c] + farfield * dir[c];
                m.control[3 * static_cast<std::size_t>(g) + c] =
                    (k == 0) ? wall : wall + t[k] * (far - wall);
            }
        }
    }

    // Grid parameters: uniform along the wall, clustered towards it radially with a smoothly
    // growing physical spacing (radialSamples), measured on a column of the body radius.
    const std::vector<double> radialKnots = nurbs::uniformKnots(o.radialDegree, nk);
    const std::vector<double> radial = radialSamples(
        radialKnots, o.radialDegree, geometricLayers(nk, o.controlWallSpacing * radius / (farfield - radius)),
        o.radialNodes - 1, o.gridWallSpacing * radius / (farfield - radius), o.refine);
    const std::vector<double> along = uniformSamples(o.surfaceNodes - 1, o.refine);

    const geometry::Adjacency adj = geometry::buildAdjacency(set, 1e-9);
    for (int p = 0; p < set.size(); ++p) {
        const geometry::Patch& patch = set.patches[p];
        if (patch.rational()) {
            throw GeometryError("mesh: " + set.describe(p) +
                                " is rational; mesh blocks are polynomial B-spline volumes");
        }
        ControlBlock b;
        b.name = p < static_cast<int>(set.names.size()) && !set.names[p].empty()
                     ? set.names[p]
                     : "block " + std::to_string(p + 1);
        b.degree = {patch.degreeU, patch.degreeV, o.radialDegree};
        b.count = {patch.countU, patch.countV, nk};
        b.knots = {patch.knotsU, patch.knotsV, radialKnots};
        b.nodes.resize(static_cast<std::size_t>(patch.countU) * patch.countV * nk);
        for (int k = 0; k < nk; ++k) {
            for (int j = 0; j < patch.countV; ++j) {
                for (int i = 0; i < patch.countU; ++i) {
                    const int u = idx.toUnique[idx.patchOffset[p] + patch.index(i, j)];
                    b.nodes[b.local(i, j, k)] = u + nu * k;
                }
            }
        }
        // Normalize the patch parameter range to the samples.
        for (int d = 0; d < 2; ++d) {
            const auto& U = b.knots[d];
            b.samples[d].resize(along.size());
            for (std::size_t s = 0; s < along.size(); ++s) {
                b.samples[d][s] = (s + 1 == along.size())
                                      ? U.back()
                                      : U.front() + along[s] * (U.back() - U.front());
            }
        }
        b.samples[2] = radial;
        b.faces[static_cast<int>(Face::KMin)].kind = BoundaryKind::Wall;
        b.faces[static_cast<int>(Face::KMax)].kind = BoundaryKind::Farfield;
        m.blocks.push_back(std::move(b));
    }
    for (const geometry::SharedEdge& s : adj.shared) {
        const int fa = kEdgeFace[s.a.edge], fb = kEdgeFace[s.b.edge];
        m.blocks[s.a.patch].faces[fa] = {BoundaryKind::Interface, s.b.patch, fb};
        m.blocks[s.b.patch].faces[fb] = {BoundaryKind::Interface, s.a.patch, fa};
    }
    for (const geometry::EdgeRef& e : adj.free) {
        const nurbs::Curve<double> c = nurbs::boundaryCurve(set.patches[e.patch], e.edge);
        for (int i = 0; i < c.count(); ++i) {
            if (std::abs(c.points[3 * i + 1]) > o.symmetryTolerance) {
                throw GeometryError(
                    "mesh: edge " + std::to_string(e.edge) + " of " + set.describe(e.patch) +
                    " is neither shared with another patch nor on the symmetry plane Y = 0");
            }
        }
        m.blocks[e.patch].faces[kEdgeFace[e.edge]].kind = BoundaryKind::Symmetry;
    }
    validate(m);
    matchInterfaces(m, regenerateAll(m));
    return m;
}

}  // namespace aero::mesh
