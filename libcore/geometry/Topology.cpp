#include "geometry/Topology.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "nurbs/Inversion.h"

namespace aero::geometry {

using nurbs::Vec3;

ControlPointIndex buildControlPointIndex(const PatchSet& set, double tolerance) {
    ControlPointIndex idx;
    idx.tolerance = tolerance;
    idx.patchOffset.resize(set.patches.size() + 1, 0);
    for (std::size_t p = 0; p < set.patches.size(); ++p) {
        idx.patchOffset[p + 1] = idx.patchOffset[p] + set.patches[p].controlCount();
    }
    idx.toUnique.resize(idx.patchOffset.back());
    // Spatial hash with cells of size h >= tolerance: a match lies in one of 27 cells.
    const double h = std::max(tolerance, 1e-300) * 2.0;
    auto cell = [h](double x) { return static_cast<long long>(std::floor(x / h)); };
    auto key = [](long long i, long long j, long long k) {
        return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
    };
    std::unordered_multimap<long long, int> grid;
    grid.reserve(idx.toUnique.size());
    int a = 0;
    for (const Patch& patch : set.patches) {
        for (int c = 0; c < patch.controlCount(); ++c, ++a) {
            const double* x = &patch.points[3 * c];
            const long long ci = cell(x[0]), cj = cell(x[1]), ck = cell(x[2]);
            int found = -1;
            for (long long di = -1; di <= 1 && found < 0; ++di) {
                for (long long dj = -1; dj <= 1 && found < 0; ++dj) {
                    for (long long dk = -1; dk <= 1 && found < 0; ++dk) {
                        auto range = grid.equal_range(key(ci + di, cj + dj, ck + dk));
                        for (auto it = range.first; it != range.second; ++it) {
                            const double* y = &idx.points[3 * it->second];
                            const double d = std::sqrt((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                                       (x[2] - y[2]) * (x[2] - y[2]));
                            if (d <= tolerance) {
                                found = it->second;
                                break;
                            }
                        }
                    }
                }
            }
            if (found < 0) {
                found = idx.uniqueCount();
                idx.points.insert(idx.points.end(), x, x + 3);
                grid.emplace(key(ci, cj, ck), found);
            }
            idx.toUnique[a] = found;
        }
    }
    return idx;
}

namespace {

struct EdgeInfo {
    nurbs::Curve<double> curve;
    Vec3<double> start, end, mid;
    double length = 0;  // chord of the control polygon, a scale for tolerances
};

Vec3<double> point(const nurbs::Curve<double>& c, int i) {
    return Vec3<double>(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2]);
}

// Largest distance from curve a to curve b (one-sided Hausdorff distance): dense samples,
// then a golden-section refinement of the worst one, so the maximum is not missed by O(h^2).
double oneSidedGap(const nurbs::Curve<double>& a, const nurbs::Curve<double>& b) {
    constexpr int kSamples = 33;
    nurbs::InversionOptions o;
    o.tolerance = 1e-15;
    auto distance = [&](double u) { return nurbs::project(b, nurbs::evaluate(a, u), o).distance; };
    const double h = (a.last() - a.first()) / (kSamples - 1);
    double gap = 0, worst = a.first();
    for (int s = 0; s < kSamples; ++s) {
        const double u = a.first() + h * s;
        const double d = distance(u);
        if (d > gap) {
            gap = d;
            worst = u;
        }
    }
    if (gap == 0) return 0;
    double lo = std::max(a.first(), worst - h), hi = std::min(a.last(), worst + h);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = distance(x1), f2 = distance(x2);
    for (int it = 0; it < 40; ++it) {
        if (f1 > f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = distance(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = distance(x2);
        }
    }
    return std::max({gap, f1, f2});
}

// Max distance between corresponding control points (in order or reversed), or +inf if the
// two curves do not have matching degree, knots (reversed when needed) and counts.
double netDifference(const nurbs::Curve<double>& a, const nurbs::Curve<double>& b, bool reversed) {
    if (a.degree != b.degree || a.count() != b.count() || a.rational() != b.rational()) {
        return std::numeric_limits<double>::infinity();
    }
    const int n = a.count();
    double d = 0;
    for (int i = 0; i < n; ++i) {
        const int j = reversed ? n - 1 - i : i;
        d = std::max(d, (point(a, i) - point(b, j)).norm());
        if (a.rational() && a.weights[i] != b.weights[j]) return std::numeric_limits<double>::infinity();
    }
    return d;
}

// Same knot vectors up to an affine reparameterization (reversed when the edges run opposite).
bool equivalentKnots(const nurbs::Curve<double>& a, const nurbs::Curve<double>& b, bool reversed) {
    if (a.knots.size() != b.knots.size()) return false;
    const std::size_t n = a.knots.size();
    const double la = a.last() - a.first(), lb = b.last() - b.first();
    for (std::size_t i = 0; i < n; ++i) {
        const double ta = (a.knots[i] - a.first()) / la;
        const double tb = reversed ? (b.last() - b.knots[n - 1 - i]) / lb : (b.knots[i] - b.first()) / lb;
        if (std::abs(ta - tb) > 1e-14) return false;
    }
    return true;
}

}  // namespace

Adjacency buildAdjacency(const PatchSet& set, double tolerance) {
    std::vector<EdgeInfo> edges;
    std::vector<EdgeRef> refs;
    for (int p = 0; p < set.size(); ++p) {
        for (int e = 0; e < 4; ++e) {
            EdgeInfo info;
            info.curve = nurbs::boundaryCurve(set.patches[p], e);
            const int n = info.curve.count();
            info.start = point(info.curve, 0);
            info.end = point(info.curve, n - 1);
            info.mid = nurbs::evaluate(info.curve, 0.5 * (info.curve.first() + info.curve.last()));
            for (int i = 1; i < n; ++i) info.length += (point(info.curve, i) - point(info.curve, i - 1)).norm();
            edges.push_back(std::move(info));
            refs.push_back({p, e});
        }
    }
    Adjacency adj;
    std::vector<bool> used(edges.size(), false);
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (used[i]) continue;
        const EdgeInfo& a = edges[i];
        if (a.length <= tolerance) {  // degenerate edge (a pole): nothing to share
            adj.free.push_back(refs[i]);
            continue;
        }
        // A partner's midpoint must lie close to ours: within 1% of the edge length.
        const double midTol = std::max(tolerance, 1e-2 * a.length);
        for (std::size_t j = i + 1; j < edges.size(); ++j) {
            if (used[j] || refs[j].patch == refs[i].patch) continue;
            const EdgeInfo& b = edges[j];
            const bool same = (a.start - b.start).norm() <= tolerance && (a.end - b.end).norm() <= tolerance;
            const bool rev = (a.start - b.end).norm() <= tolerance && (a.end - b.start).norm() <= tolerance;
            if ((!same && !rev) || (a.mid - b.mid).norm() > midTol) continue;
            SharedEdge s;
            s.a = refs[i];
            s.b = refs[j];
            s.reversed = !same;
            s.identicalNets = netDifference(a.curve, b.curve, s.reversed) == 0.0;
            // Identical nets over equivalent knot vectors are the same curve: no gap at all.
            s.gap = (s.identicalNets && equivalentKnots(a.curve, b.curve, s.reversed))
                        ? 0.0
                        : std::max(oneSidedGap(a.curve, b.curve), oneSidedGap(b.curve, a.curve));
            adj.maxGap = std::max(adj.maxGap, s.gap);
            adj.shared.push_back(s);
            used[i] = used[j] = true;
            break;
        }
        if (!used[i]) adj.free.push_back(refs[i]);
    }
    return adj;
}

namespace {

constexpr int kPieceSamples = 33;

struct Piece {
    int patch = -1;
    TrimCurve curve;
    std::vector<Vec3<double>> samples;  // kPieceSamples points of S(c(t)), uniform in t
    std::vector<double> t;
    double length = 0;
    Vec3<double> lo, hi;  // bounding box of the samples
};

Vec3<double> image(const PatchSet& set, const Piece& p, double t) {
    const Point2 uv = evaluate(p.curve, t);
    return nurbs::evaluate(set.patches[static_cast<std::size_t>(p.patch)], uv[0], uv[1]);
}

/// Golden-section search for the extremum of f on [lo, hi] (`steps` steps); `maximum` picks which.
template <class F>
double golden(F f, double lo, double hi, bool maximum, double& best, int steps = 40) {
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = f(x1), f2 = f(x2);
    auto better = [&](double a, double b) { return maximum ? a > b : a < b; };
    for (int it = 0; it < steps; ++it) {
        if (better(f1, f2)) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    best = better(f1, f2) ? x1 : x2;
    return better(f1, f2) ? f1 : f2;
}

/// Distance from x to the piece's image: refined (golden section) in every interval between two
/// samples where the curve can come nearer than the best found so far. By the triangle
/// inequality a point of the arc between samples a and b, of length L, is at least
/// (d_a + d_b - L) / 2 from x; L is taken as 1.1 times the chord. Not only around the nearest
/// sample: near a thin trailing edge or leading edge of a closed airfoil loop the nearest sample
/// can lie on the other surface (an Onshape wing's tip edge measured 1 mm, the airfoil's
/// thickness there, from a neighbour 2e-6 away).
double distanceTo(const PatchSet& set, const Piece& p, const Vec3<double>& x) {
    const std::size_t n = p.samples.size();
    std::vector<double> d(n);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
        d[i] = (p.samples[i] - x).norm();
        best = std::min(best, d[i]);
    }
    if (best == 0) return 0;
    // Intervals in order of their lower bound, so the nearest is refined first and the bound
    // then prunes the rest.
    std::vector<std::pair<double, std::size_t>> intervals;
    for (std::size_t k = 0; k + 1 < n; ++k) {
        const double chord = (p.samples[k + 1] - p.samples[k]).norm();
        intervals.emplace_back(0.5 * (d[k] + d[k + 1] - 1.1 * chord), k);
    }
    std::sort(intervals.begin(), intervals.end());
    for (const auto& [bound, k] : intervals) {
        if (bound >= best) break;
        double at = 0;
        // The distance is V-shaped at a point on the curve: 80 steps shrink the bracket to round-off.
        best = std::min(best, golden([&](double t) { return (image(set, p, t) - x).norm(); }, p.t[k], p.t[k + 1],
                                     false, at, 80));
    }
    return best;
}

double distanceToBox(const Piece& p, const Vec3<double>& x) {
    return (x.cwiseMax(p.lo).cwiseMin(p.hi) - x).norm();
}

}  // namespace

BoundaryGaps boundaryGaps(const PatchSet& set, double tolerance) {
    std::vector<Piece> pieces;
    for (int p = 0; p < set.size(); ++p) {
        const Patch& s = set.patches[static_cast<std::size_t>(p)];
        const TrimLoop rectangle = rectangleLoop(s.knotsU[static_cast<std::size_t>(s.degreeU)], s.knotsU[static_cast<std::size_t>(s.countU)],
                                                 s.knotsV[static_cast<std::size_t>(s.degreeV)], s.knotsV[static_cast<std::size_t>(s.countV)]);
        std::vector<const TrimLoop*> loops{&rectangle};
        if (set.trimmed(p)) {
            const PatchTrim& trim = set.trims[static_cast<std::size_t>(p)];
            if (!trim.outer.curves.empty()) loops[0] = &trim.outer;
            for (const TrimLoop& h : trim.holes) loops.push_back(&h);
        }
        for (const TrimLoop* loop : loops)
            for (const TrimCurve& c : loop->curves) {
                Piece piece;
                piece.patch = p;
                piece.curve = c;
                for (int k = 0; k < kPieceSamples; ++k) {
                    piece.t.push_back(c.first + (c.last - c.first) * k / (kPieceSamples - 1));
                    piece.samples.push_back(image(set, piece, piece.t.back()));
                    if (k > 0) piece.length += (piece.samples[k] - piece.samples[k - 1]).norm();
                }
                piece.lo = piece.hi = piece.samples[0];
                for (const auto& x : piece.samples) {
                    piece.lo = piece.lo.cwiseMin(x);
                    piece.hi = piece.hi.cwiseMax(x);
                }
                pieces.push_back(std::move(piece));
            }
    }

    BoundaryGaps out;
    for (const Piece& a : pieces) {
        if (a.length <= tolerance) continue;  // a degenerate edge (a pole)
        ++out.pieces;
        const double matchDistance = std::max(tolerance, 1e-2 * a.length);
        const Vec3<double>& mid = a.samples[kPieceSamples / 2];
        // The boundaries a piece can lie along: the other patches', and its own patch's other
        // pieces where they coincide with it (a closed skin's seam, e.g. the two ends of a wing
        // skin that wraps round the trailing edge). Not its own patch's within the 1 % (a thin
        // strip's two long edges are not a gap).
        std::vector<const Piece*> others;
        for (const Piece& b : pieces) {
            if (&b == &a) continue;
            if (b.patch != a.patch) {
                others.push_back(&b);
            } else if (b.length > tolerance && distanceToBox(b, mid) <= tolerance &&
                       distanceTo(set, b, mid) <= tolerance) {
                others.push_back(&b);
            }
        }
        int best = -1;
        double bestDistance = std::numeric_limits<double>::infinity();
        for (const Piece* b : others) {
            if (distanceToBox(*b, mid) > std::min(matchDistance, bestDistance)) continue;
            const double d = distanceTo(set, *b, mid);
            if (d < bestDistance) {
                bestDistance = d;
                best = b->patch;
            }
        }
        if (best < 0 || bestDistance > matchDistance) {
            ++out.free;
            continue;
        }
        ++out.matched;
        // The distance to every other patch's boundary, not only the one found at the midpoint:
        // a long edge may lie along several patches on the other side (a T-junction; the KCS
        // hull's edges measured 29 m against the one patch at their midpoints).
        // Nearest boxes first: the first distance found then rules out most of the others.
        std::vector<std::pair<double, const Piece*>> byBox(others.size());
        auto gapAt = [&](const Vec3<double>& x) {
            for (std::size_t i = 0; i < others.size(); ++i) byBox[i] = {distanceToBox(*others[i], x), others[i]};
            std::sort(byBox.begin(), byBox.end(),
                      [](const auto& l, const auto& r) { return l.first < r.first; });
            double d = std::numeric_limits<double>::infinity();
            for (const auto& [box, b] : byBox) {
                if (box >= d) break;
                d = std::min(d, distanceTo(set, *b, x));
            }
            return d;
        };
        // Parts farther from every other boundary than the matching distance (1 % of the piece's
        // length) are not a gap but free boundary (an edge that runs on past the patches along
        // it, e.g. onto the symmetry plane): left out of the gap, the piece counted partly free.
        double gap = 0;
        std::size_t worst = 0;
        bool partly = false;
        for (std::size_t k = 0; k < a.samples.size(); ++k) {
            const double d = gapAt(a.samples[k]);
            if (d > matchDistance) {
                partly = true;
            } else if (d > gap) {
                gap = d;
                worst = k;
            }
        }
        out.partlyFree += partly ? 1 : 0;
        Vec3<double> where = a.samples[worst];
        if (gap > 0) {
            double at = 0;
            const double lo = a.t[worst == 0 ? 0 : worst - 1], hi = a.t[std::min(worst + 1, a.t.size() - 1)];
            const double refined = golden([&](double t) { return gapAt(image(set, a, t)); }, lo, hi, true, at);
            if (refined > gap && refined <= matchDistance) {
                gap = refined;
                where = image(set, a, at);
            }
        }
        if (gap > out.maxGap || out.worstPatch < 0) {
            out.maxGap = std::max(out.maxGap, gap);
            out.worstPatch = a.patch;
            out.worstPoint = {where[0], where[1], where[2]};
        }
    }
    return out;
}

}  // namespace aero::geometry
