#include "mesh/Quality.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <queue>
#include <tuple>

#include "common/Error.h"
#include "common/Scalar.h"

namespace aero::mesh {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

inline double dot(const double* a, const double* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// det[a, b, c] with a, b, c as columns = a . (b x c).
inline double det3(const double* a, const double* b, const double* c) {
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// Locale-independent short form of a number for messages (printf would follow LC_NUMERIC,
// which a GUI may have set to a comma locale).
std::string num(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
    return std::string(buf, r.ptr);
}

std::string blockLabel(const std::vector<StructuredGrid>& blocks, int b) {
    return "block " + std::to_string(b) + " '" + blocks[b].name + "'";
}

std::array<int, 3> cellIjk(const StructuredGrid& g, long c) {
    const long ni = g.dims[0] - 1, nj = g.dims[1] - 1;
    return {static_cast<int>(c % ni), static_cast<int>((c / ni) % nj),
            static_cast<int>(c / (ni * nj))};
}

std::array<double, 3> centroid(const StructuredGrid& g, const std::array<int, 3>& c) {
    std::array<double, 3> s{0, 0, 0};
    for (int n = 0; n < 8; ++n) {
        const double* x = g.at(c[0] + (n & 1), c[1] + ((n >> 1) & 1), c[2] + ((n >> 2) & 1));
        for (int d = 0; d < 3; ++d) s[d] += x[d];
    }
    for (double& v : s) v *= 0.125;
    return s;
}

CellLocation locate(const std::vector<StructuredGrid>& blocks, int b, long c, double value) {
    CellLocation loc;
    loc.block = b;
    loc.blockName = blocks[b].name;
    loc.cell = cellIjk(blocks[b], c);
    loc.centroid = centroid(blocks[b], loc.cell);
    loc.value = value;
    return loc;
}

void checkMatch(const std::vector<StructuredGrid>& blocks, const std::vector<CellQuality>& q) {
    if (q.size() != blocks.size()) {
        throw Error("cell quality: " + std::to_string(q.size()) + " quality sets for " +
                    std::to_string(blocks.size()) + " blocks");
    }
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        const std::size_t n = static_cast<std::size_t>(std::max(0L, blocks[b].cellCount()));
        const CellQuality& c = q[b];
        for (const auto* v :
             {&c.minJacobian, &c.scaledJacobian, &c.orthogonality, &c.aspectRatio, &c.skewness}) {
            if (v->size() != n) {
                throw Error("cell quality: " + blockLabel(blocks, static_cast<int>(b)) + " has " +
                            std::to_string(n) + " cells but a metric has " +
                            std::to_string(v->size()) + " values");
            }
        }
    }
}

// min/max/mean/histogram of one metric over all blocks. fixedLo/fixedHi: NaN = from the data.
MetricSummary summarizeMetric(const std::vector<const std::vector<double>*>& values, double fixedLo,
                              double fixedHi) {
    MetricSummary s;
    s.min = kInf;
    s.max = -kInf;
    double sum = 0, finiteMin = kInf, finiteMax = -kInf;
    long finite = 0;
    for (const auto* v : values) {
        for (const double x : *v) {
            if (std::isnan(x)) {
                ++s.nonFinite;
                continue;
            }
            s.min = std::min(s.min, x);
            s.max = std::max(s.max, x);
            if (std::isinf(x)) {
                ++s.nonFinite;
                continue;
            }
            finiteMin = std::min(finiteMin, x);
            finiteMax = std::max(finiteMax, x);
            sum += x;
            ++finite;
        }
    }
    if (s.min > s.max) s.min = s.max = kNaN;  // no comparable value at all
    s.mean = finite > 0 ? sum / static_cast<double>(finite) : kNaN;
    s.lo = std::isnan(fixedLo) ? finiteMin : fixedLo;
    s.hi = std::isnan(fixedHi) ? finiteMax : fixedHi;
    if (finite == 0) s.lo = s.hi = 0;
    const double width = s.hi - s.lo;
    for (const auto* v : values) {
        for (const double x : *v) {
            if (!std::isfinite(x)) continue;
            int bin = 0;
            if (width > 0) {
                const double t = (x - s.lo) / width * kQualityBins;
                bin = t <= 0 ? 0 : (t >= kQualityBins ? kQualityBins - 1 : static_cast<int>(t));
            }
            ++s.histogram[bin];
        }
    }
    return s;
}

}  // namespace

CellQuality cellQuality(const StructuredGrid& g) {
    for (int d = 0; d < 3; ++d) {
        if (g.dims[d] < 2) {
            throw GeometryError("cell quality of block '" + g.name +
                                "': dims must be at least 2, got " + std::to_string(g.dims[0]) +
                                " x " + std::to_string(g.dims[1]) + " x " +
                                std::to_string(g.dims[2]));
        }
    }
    if (g.xyz.size() != 3 * static_cast<std::size_t>(g.nodeCount())) {
        throw GeometryError("cell quality of block '" + g.name + "': xyz has " +
                            std::to_string(g.xyz.size()) + " values, expected 3 * " +
                            std::to_string(g.nodeCount()));
    }
    const long n = g.cellCount();
    CellQuality q;
    q.minJacobian.resize(n);
    q.scaledJacobian.resize(n);
    q.orthogonality.resize(n);
    q.aspectRatio.resize(n);
    q.skewness.resize(n);
    const int ni = g.dims[0] - 1, nj = g.dims[1] - 1, nk = g.dims[2] - 1;

#pragma omp parallel for schedule(static) if (n > 4096)
    for (int k = 0; k < nk; ++k) {
        for (int j = 0; j < nj; ++j) {
            for (int i = 0; i < ni; ++i) {
                // Corner n = a + 2b + 4c sits at node (i+a, j+b, k+c).
                const double* X[8];
                for (int c = 0; c < 8; ++c) {
                    X[c] = g.at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                }
                // E[d][e]: the 4 edges of direction d, oriented +d; e numbers the other two
                // offsets (d = 0: e = b + 2c, d = 1: e = a + 2c, d = 2: e = a + 2b).
                double E[3][4][3], U[3][4][3], L[3][4];
                for (int e = 0; e < 4; ++e) {
                    const int lo[3] = {2 * e, (e & 1) + 4 * (e >> 1), e};
                    const int step[3] = {1, 2, 4};
                    for (int d = 0; d < 3; ++d) {
                        const double* p = X[lo[d]];
                        const double* r = X[lo[d] + step[d]];
                        for (int m = 0; m < 3; ++m) E[d][e][m] = r[m] - p[m];
                        L[d][e] = std::sqrt(dot(E[d][e], E[d][e]));
                        const double inv = L[d][e] > 0 ? 1.0 / L[d][e] : 0.0;
                        for (int m = 0; m < 3; ++m) U[d][e][m] = E[d][e][m] * inv;
                    }
                }
                double minJ = kInf, minS = kInf, maxCos = 0, probe = 0;
                for (int c = 0; c < 8; ++c) {
                    const int a = c & 1, b = (c >> 1) & 1, cc = c >> 2;
                    const int e0 = b + 2 * cc, e1 = a + 2 * cc, e2 = a + 2 * b;
                    const double J = det3(E[0][e0], E[1][e1], E[2][e2]);
                    const double S = det3(U[0][e0], U[1][e1], U[2][e2]);
                    probe += J + S;
                    minJ = std::min(minJ, J);
                    minS = std::min(minS, S);
                    // An angle at a zero-length edge is undefined: count it as the worst.
                    const bool z0 = !(L[0][e0] > 0), z1 = !(L[1][e1] > 0), z2 = !(L[2][e2] > 0);
                    const double c01 = (z0 || z1) ? 1.0 : std::abs(dot(U[0][e0], U[1][e1]));
                    const double c12 = (z1 || z2) ? 1.0 : std::abs(dot(U[1][e1], U[2][e2]));
                    const double c02 = (z0 || z2) ? 1.0 : std::abs(dot(U[0][e0], U[2][e2]));
                    maxCos = std::max({maxCos, c01, c12, c02});
                }
                // Principal axes and mean edge lengths.
                double A[3][3], mean[3];
                bool zeroAxis = false;
                for (int d = 0; d < 3; ++d) {
                    for (int m = 0; m < 3; ++m) {
                        A[d][m] = E[d][0][m] + E[d][1][m] + E[d][2][m] + E[d][3][m];
                    }
                    const double len = std::sqrt(dot(A[d], A[d]));
                    zeroAxis = zeroAxis || !(len > 0);
                    const double inv = len > 0 ? 1.0 / len : 0.0;
                    for (int m = 0; m < 3; ++m) A[d][m] *= inv;
                    mean[d] = 0.25 * (L[d][0] + L[d][1] + L[d][2] + L[d][3]);
                }
                const double skew =
                    zeroAxis ? 1.0
                             : std::max({std::abs(dot(A[0], A[1])), std::abs(dot(A[1], A[2])),
                                         std::abs(dot(A[0], A[2]))});
                const double shortest = std::min({mean[0], mean[1], mean[2]});
                const double longest = std::max({mean[0], mean[1], mean[2]});
                const long idx = g.cell(i, j, k);
                if (std::isnan(probe)) {  // NaN/inf coordinates: every metric is NaN
                    q.minJacobian[idx] = q.scaledJacobian[idx] = q.orthogonality[idx] = kNaN;
                    q.aspectRatio[idx] = q.skewness[idx] = kNaN;
                    continue;
                }
                q.minJacobian[idx] = minJ;
                q.scaledJacobian[idx] = std::clamp(minS, -1.0, 1.0);
                q.orthogonality[idx] = 1.0 - std::min(maxCos, 1.0);
                q.aspectRatio[idx] = shortest > 0 ? longest / shortest : kInf;
                q.skewness[idx] = std::min(skew, 1.0);
            }
        }
    }
    return q;
}

QualitySummary summarize(const std::vector<StructuredGrid>& blocks,
                         const std::vector<CellQuality>& q, int worst) {
    checkMatch(blocks, q);
    QualitySummary s;
    auto gather = [&](std::vector<double> CellQuality::*m) {
        std::vector<const std::vector<double>*> v;
        for (const CellQuality& c : q) v.push_back(&(c.*m));
        return v;
    };
    s.minJacobian = summarizeMetric(gather(&CellQuality::minJacobian), kNaN, kNaN);
    s.scaledJacobian = summarizeMetric(gather(&CellQuality::scaledJacobian), -1.0, 1.0);
    s.orthogonality = summarizeMetric(gather(&CellQuality::orthogonality), 0.0, 1.0);
    s.aspectRatio = summarizeMetric(gather(&CellQuality::aspectRatio), 1.0, kNaN);
    s.skewness = summarizeMetric(gather(&CellQuality::skewness), 0.0, 1.0);
    if (s.aspectRatio.hi < s.aspectRatio.lo) s.aspectRatio.hi = s.aspectRatio.lo;

    // Worst cells: a max-heap of the `worst` lowest (value, block, cell) keys, NaN as -inf.
    using Key = std::tuple<double, int, long>;
    std::priority_queue<Key> heap;
    for (int b = 0; b < static_cast<int>(q.size()); ++b) {
        const std::vector<double>& sj = q[b].scaledJacobian;
        const std::vector<double>& mj = q[b].minJacobian;
        for (long c = 0; c < static_cast<long>(sj.size()); ++c) {
            ++s.cellCount;
            if (!(mj[c] > 0)) ++s.nonPositiveJacobian;
            if (worst <= 0) continue;
            const double v = std::isnan(sj[c]) ? -kInf : sj[c];
            if (static_cast<int>(heap.size()) < worst) {
                heap.emplace(v, b, c);
            } else if (v < std::get<0>(heap.top())) {
                // Cells are scanned in increasing (block, cell) order, so an equal value never
                // displaces a kept cell: ties keep the first cells.
                heap.pop();
                heap.emplace(v, b, c);
            }
        }
    }
    s.worst.resize(heap.size());
    for (auto it = s.worst.rbegin(); it != s.worst.rend(); ++it) {
        const auto [value, b, c] = heap.top();
        heap.pop();
        *it = locate(blocks, b, c, q[b].scaledJacobian[c]);
    }
    return s;
}

void requirePositiveJacobians(const std::vector<StructuredGrid>& blocks,
                              const std::vector<CellQuality>& q) {
    checkMatch(blocks, q);
    long bad = 0, total = 0;
    int firstBlock = -1;
    long firstCell = -1;
    for (int b = 0; b < static_cast<int>(q.size()); ++b) {
        const std::vector<double>& mj = q[b].minJacobian;
        total += static_cast<long>(mj.size());
        for (long c = 0; c < static_cast<long>(mj.size()); ++c) {
            if (mj[c] > 0) continue;
            if (bad++ == 0) {
                firstBlock = b;
                firstCell = c;
            }
        }
    }
    if (bad == 0) return;
    const CellLocation at =
        locate(blocks, firstBlock, firstCell, q[firstBlock].minJacobian[firstCell]);
    throw GeometryError("non-positive cell Jacobian: " + blockLabel(blocks, firstBlock) +
                        ", cell (" + std::to_string(at.cell[0]) + ", " +
                        std::to_string(at.cell[1]) + ", " + std::to_string(at.cell[2]) +
                        ") at centroid (" + num(at.centroid[0]) + ", " + num(at.centroid[1]) +
                        ", " + num(at.centroid[2]) + "): minimum Jacobian determinant " +
                        num(at.value) + "; " + std::to_string(bad) + " of " +
                        std::to_string(total) + " cells are non-positive");
}

SpacingJump largestSpacingJump(const std::vector<StructuredGrid>& blocks) {
    SpacingJump out;
    auto edge = [](const double* a, const double* b) {
        const double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        return std::sqrt(dot(d, d));
    };
    for (int b = 0; b < static_cast<int>(blocks.size()); ++b) {
        const StructuredGrid& g = blocks[b];
        if (static_cast<long>(g.xyz.size()) != 3 * g.nodeCount()) {
            throw Error("largestSpacingJump: " + blockLabel(blocks, b) + " has " + std::to_string(g.xyz.size()) +
                        " coordinates for " + std::to_string(g.nodeCount()) + " nodes");
        }
        for (int k = 0; k < g.dims[2]; ++k) {
            for (int j = 0; j < g.dims[1]; ++j) {
                for (int i = 0; i < g.dims[0]; ++i) {
                    const std::array<int, 3> n{i, j, k};
                    for (int d = 0; d < 3; ++d) {
                        if (n[d] == 0 || n[d] == g.dims[d] - 1) continue;
                        std::array<int, 3> lo = n, hi = n;
                        --lo[d];
                        ++hi[d];
                        const double* x = g.at(i, j, k);
                        const double a = edge(g.at(lo[0], lo[1], lo[2]), x);
                        const double c = edge(x, g.at(hi[0], hi[1], hi[2]));
                        if (a == 0 && c == 0) continue;
                        const double ratio = std::max(a, c) / std::min(a, c);  // +inf if one is 0
                        if (!(ratio > out.ratio)) continue;                     // NaN never wins
                        out.ratio = ratio;
                        out.block = b;
                        out.blockName = g.name;
                        out.direction = d;
                        out.node = n;
                        out.x = {x[0], x[1], x[2]};
                    }
                }
            }
        }
    }
    return out;
}

namespace {

// A pair of neighbouring nodes on a wall face and the points their normals come from: node a's
// (a = 0, 1) normal is (x[p[a][1]] - x[p[a][0]]) x (x[p[a][3]] - x[p[a][2]]), the differences
// along the face's two tangential directions (central inside the face, one-sided at its edges).
struct WallPair {
    int block = 0;
    std::array<int, 3> node{0, 0, 0}, neighbour{0, 0, 0};
    long p[2][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}};
};

std::vector<WallPair> wallPairs(const std::vector<StructuredGrid>& blocks, const std::vector<std::array<bool, 6>>& wallFaces,
                                const char* who) {
    if (wallFaces.size() != blocks.size()) {
        throw Error(std::string(who) + ": " + std::to_string(wallFaces.size()) + " face lists for " +
                    std::to_string(blocks.size()) + " blocks");
    }
    std::vector<WallPair> out;
    for (int b = 0; b < static_cast<int>(blocks.size()); ++b) {
        const StructuredGrid& g = blocks[b];
        if (static_cast<long>(g.xyz.size()) != 3 * g.nodeCount()) {
            throw Error(std::string(who) + ": " + blockLabel(blocks, b) + " has " + std::to_string(g.xyz.size()) +
                        " coordinates for " + std::to_string(g.nodeCount()) + " nodes");
        }
        for (int f = 0; f < 6; ++f) {
            if (!wallFaces[b][f]) continue;
            const int d = f / 2;                         // the face's normal direction
            const int s = (d + 1) % 3, t = (d + 2) % 3;  // its tangential directions (right-handed)
            const int fixed = f % 2 == 1 ? g.dims[d] - 1 : 0;
            const int ns = g.dims[s], nt = g.dims[t];
            auto ijk = [&](int a, int c) {
                std::array<int, 3> n{0, 0, 0};
                n[d] = fixed;
                n[s] = a;
                n[t] = c;
                return n;
            };
            auto id = [&](int a, int c) {
                const std::array<int, 3> n = ijk(a, c);
                return g.node(n[0], n[1], n[2]);
            };
            auto stencil = [&](int a, int c, long* p) {
                p[0] = id(std::max(a - 1, 0), c);
                p[1] = id(std::min(a + 1, ns - 1), c);
                p[2] = id(a, std::max(c - 1, 0));
                p[3] = id(a, std::min(c + 1, nt - 1));
            };
            for (int c = 0; c < nt; ++c) {
                for (int a = 0; a < ns; ++a) {
                    for (int step = 0; step < 2; ++step) {
                        const int a1 = a + (step == 0), c1 = c + (step == 1);
                        if (a1 >= ns || c1 >= nt) continue;
                        WallPair w;
                        w.block = b;
                        w.node = ijk(a, c);
                        w.neighbour = ijk(a1, c1);
                        stencil(a, c, w.p[0]);
                        stencil(a1, c1, w.p[1]);
                        out.push_back(w);
                    }
                }
            }
        }
    }
    return out;
}

// Node a's unnormalized normal w = u x v from the block's coordinates.
template <class T>
void pairNormal(const T* x, const WallPair& w, int a, T u[3], T v[3], T n[3]) {
    for (int m = 0; m < 3; ++m) {
        u[m] = x[3 * w.p[a][1] + m] - x[3 * w.p[a][0] + m];
        v[m] = x[3 * w.p[a][3] + m] - x[3 * w.p[a][2] + m];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

// s = 1 - n0 . n1 of a pair's unit normals (2 sin^2 of half the angle: smooth where the angle is
// 0, unlike the angle); false when a normal is undefined (a collapsed edge).
template <class T>
bool pairMeasure(const T* x, const WallPair& w, T& s) {
    T u[3], v[3], n0[3], n1[3];
    pairNormal(x, w, 0, u, v, n0);
    pairNormal(x, w, 1, u, v, n1);
    const T l0 = n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2];
    const T l1 = n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2];
    if (realPart(l0) == 0 || realPart(l1) == 0) return false;
    s = T(1.0) - (n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2]) / std::sqrt(l0 * l1);
    return true;
}

// The angle in degrees whose 1 - cos is s (s in [0, 2]).
template <class T>
T degreesOfMeasure(const T& s) {
    return T(360.0 / std::numbers::pi) * std::asin(std::sqrt(s / T(2.0)));
}

}  // namespace

WallBend sharpestWallBend(const std::vector<StructuredGrid>& blocks, const std::vector<std::array<bool, 6>>& wallFaces) {
    WallBend out;
    for (const WallPair& w : wallPairs(blocks, wallFaces, "sharpestWallBend")) {
        const double* x = blocks[w.block].xyz.data();
        double u[3], v[3], n0[3], n1[3];
        pairNormal(x, w, 0, u, v, n0);
        pairNormal(x, w, 1, u, v, n1);
        if (dot(n0, n0) == 0 || dot(n1, n1) == 0) continue;
        // atan2 of |n0 x n1| and n0 . n1: accurate for small and large angles.
        const double c[3] = {n0[1] * n1[2] - n0[2] * n1[1], n0[2] * n1[0] - n0[0] * n1[2], n0[0] * n1[1] - n0[1] * n1[0]};
        const double deg = std::atan2(std::sqrt(dot(c, c)), dot(n0, n1)) * 180.0 / std::numbers::pi;
        if (!(deg > out.degrees)) continue;
        out.degrees = deg;
        out.block = w.block;
        out.blockName = blocks[w.block].name;
        out.node = w.node;
        out.neighbour = w.neighbour;
        const double* p = blocks[w.block].at(w.node[0], w.node[1], w.node[2]);
        out.x = {p[0], p[1], p[2]};
    }
    return out;
}

namespace {

// The parts of the smooth maximum S = top + log(sum) / rho over the pairs' s.
template <class T>
struct BendKs {
    std::vector<T> s;  // per pair; -1 where a normal is undefined
    double top = -1;   // the largest s (-1: none)
    T sum = T(0.0);    // sum of exp(rho (s - top)) over the defined pairs
};

// The smooth maximum over the pairs of s (Kreisselmeier-Steinhauser), in degrees.
template <class T>
T bendSmoothMax(const std::vector<WallPair>& pairs, const std::vector<const T*>& xyz, double rho, BendKs<T>& ks) {
    ks.s.assign(pairs.size(), T(-1.0));
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (pairMeasure(xyz[pairs[k].block], pairs[k], ks.s[k])) ks.top = std::max(ks.top, realPart(ks.s[k]));
    }
    if (ks.top < 0) return T(0.0);
    for (const T& x : ks.s) {
        if (realPart(x) >= 0) ks.sum += std::exp(T(rho) * (x - T(ks.top)));
    }
    const T S = T(ks.top) + std::log(ks.sum) / T(rho);
    return realPart(S) >= 2.0 ? T(180.0) : degreesOfMeasure(S);
}

}  // namespace

double wallBendSmoothMax(const std::vector<StructuredGrid>& blocks, const std::vector<std::array<bool, 6>>& wallFaces,
                         double rho, std::vector<std::vector<double>>* gradient) {
    const std::vector<WallPair> pairs = wallPairs(blocks, wallFaces, "wallBendSmoothMax");
    std::vector<const double*> xyz;
    for (const StructuredGrid& g : blocks) xyz.push_back(g.xyz.data());
    BendKs<double> ks;
    const double deg = bendSmoothMax(pairs, xyz, rho, ks);
    if (!gradient) return deg;
    gradient->assign(blocks.size(), {});
    for (std::size_t b = 0; b < blocks.size(); ++b) (*gradient)[b].assign(blocks[b].xyz.size(), 0.0);
    if (ks.top < 0 || deg <= 0 || deg >= 180) return deg;
    // d deg / dS = (180 / pi) / sin(theta); dS / ds_k = exp(rho (s_k - top)) / sum.
    const double dDeg = 180.0 / std::numbers::pi / std::sin(deg * std::numbers::pi / 180.0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (ks.s[k] < 0) continue;
        const double weight = dDeg * std::exp(rho * (ks.s[k] - ks.top)) / ks.sum;
        if (weight == 0) continue;
        const WallPair& w = pairs[k];
        const double* x = xyz[w.block];
        double* gx = (*gradient)[w.block].data();
        double u[2][3], v[2][3], n[2][3], len[2];
        for (int a = 0; a < 2; ++a) {
            pairNormal(x, w, a, u[a], v[a], n[a]);
            len[a] = std::sqrt(dot(n[a], n[a]));
            for (double& c : n[a]) c /= len[a];
        }
        const double c01 = dot(n[0], n[1]);
        // s = 1 - n0 . n1 with n = w / |w|: ds = g_a . dw_a, g_a = -(n_b - (n_a . n_b) n_a) / |w_a|,
        // and with w = u x v: g . dw = du . (v x g) + dv . (g x u).
        for (int a = 0; a < 2; ++a) {
            const int b = 1 - a;
            double g[3];
            for (int m = 0; m < 3; ++m) g[m] = -weight * (n[b][m] - c01 * n[a][m]) / len[a];
            const double du[3] = {v[a][1] * g[2] - v[a][2] * g[1], v[a][2] * g[0] - v[a][0] * g[2], v[a][0] * g[1] - v[a][1] * g[0]};
            const double dv[3] = {g[1] * u[a][2] - g[2] * u[a][1], g[2] * u[a][0] - g[0] * u[a][2], g[0] * u[a][1] - g[1] * u[a][0]};
            for (int m = 0; m < 3; ++m) {
                gx[3 * w.p[a][1] + m] += du[m];
                gx[3 * w.p[a][0] + m] -= du[m];
                gx[3 * w.p[a][3] + m] += dv[m];
                gx[3 * w.p[a][2] + m] -= dv[m];
            }
        }
    }
    return deg;
}

std::complex<double> wallBendSmoothMax(const std::vector<StructuredGrid>& blocks,
                                       const std::vector<std::vector<std::complex<double>>>& xyz,
                                       const std::vector<std::array<bool, 6>>& wallFaces, double rho) {
    const std::vector<WallPair> pairs = wallPairs(blocks, wallFaces, "wallBendSmoothMax");
    if (xyz.size() != blocks.size()) throw Error("wallBendSmoothMax: coordinates for another number of blocks");
    std::vector<const std::complex<double>*> p;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        if (xyz[b].size() != blocks[b].xyz.size()) throw Error("wallBendSmoothMax: coordinates of another size");
        p.push_back(xyz[b].data());
    }
    BendKs<std::complex<double>> ks;
    return bendSmoothMax(pairs, p, rho, ks);
}

namespace {

// The 8 corner Jacobians of cell (i, j, k) and, with `edges`, their three edge vectors and the
// nodes each edge runs between: corner c = a + 2b + 4c' at node (i+a, j+b, k+c'); its edge along
// d goes from the cell's low to high node in d through that corner's other offsets.
struct CornerEdges {
    double e[3][3];
    long from[3], to[3];
};

void cornerJacobians(const StructuredGrid& g, int i, int j, int k, double det[8], CornerEdges* edges) {
    long node[8];
    for (int c = 0; c < 8; ++c) node[c] = g.node(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
    for (int c = 0; c < 8; ++c) {
        const int a = c & 1, b = (c >> 1) & 1, cc = c >> 2;
        // The corner's edge along d: between the corner with offset 0 and 1 in d.
        const int base[3] = {b * 2 + cc * 4, a + cc * 4, a + b * 2};
        const int step[3] = {1, 2, 4};
        double e[3][3];
        for (int d = 0; d < 3; ++d) {
            const double* lo = &g.xyz[3 * node[base[d]]];
            const double* hi = &g.xyz[3 * node[base[d] + step[d]]];
            for (int m = 0; m < 3; ++m) e[d][m] = hi[m] - lo[m];
            if (edges) {
                for (int m = 0; m < 3; ++m) edges[c].e[d][m] = e[d][m];
                edges[c].from[d] = node[base[d]];
                edges[c].to[d] = node[base[d] + step[d]];
            }
        }
        det[c] = det3(e[0], e[1], e[2]);
    }
}

}  // namespace

double cornerRatioSmoothMin(const std::vector<StructuredGrid>& grids, const std::vector<StructuredGrid>& baseline,
                            double rho, std::vector<std::vector<double>>* gradient) {
    if (grids.size() != baseline.size()) throw Error("corner ratio: the grid and its baseline differ in blocks");
    std::vector<std::vector<double>> g(grids.size());  // log ratio per corner, 8 per cell
    double m = std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < grids.size(); ++b) {
        const StructuredGrid& x = grids[b];
        const StructuredGrid& x0 = baseline[b];
        if (x.dims != x0.dims) throw Error("corner ratio: block '" + x.name + "' differs from its baseline in size");
        const int ni = x.dims[0] - 1, nj = x.dims[1] - 1, nk = x.dims[2] - 1;
        g[b].resize(8 * static_cast<std::size_t>(x.cellCount()));
        double worst = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(static) reduction(min : worst)
        for (int k = 0; k < nk; ++k) {
            for (int j = 0; j < nj; ++j) {
                for (int i = 0; i < ni; ++i) {
                    double d[8], d0[8];
                    cornerJacobians(x, i, j, k, d, nullptr);
                    cornerJacobians(x0, i, j, k, d0, nullptr);
                    double* out = &g[b][8 * static_cast<std::size_t>(x.cell(i, j, k))];
                    for (int c = 0; c < 8; ++c) {
                        out[c] = d[c] > 0 && d0[c] > 0 ? std::log(d[c] / d0[c]) : -std::numeric_limits<double>::infinity();
                        worst = std::min(worst, out[c]);
                    }
                }
            }
        }
        m = std::min(m, worst);
    }
    if (gradient) gradient->clear();
    if (!std::isfinite(m)) return m;
    double sum = 0;
    for (const auto& gb : g) {
        for (double v : gb) sum += std::exp(-rho * (v - m));
    }
    const double ks = m - std::log(sum) / rho;
    if (!gradient) return ks;
    // dKS/dg = exp(-rho (g - m)) / sum; dg/dx = (d det/dx) / det with d det[e0, e1, e2]/de0 =
    // e1 x e2 (and cyclically), each edge running between two nodes.
    gradient->resize(grids.size());
    for (std::size_t b = 0; b < grids.size(); ++b) {
        const StructuredGrid& x = grids[b];
        std::vector<double>& out = (*gradient)[b];
        out.assign(x.xyz.size(), 0.0);
        const int ni = x.dims[0] - 1, nj = x.dims[1] - 1, nk = x.dims[2] - 1;
        for (int k = 0; k < nk; ++k) {
            for (int j = 0; j < nj; ++j) {
                for (int i = 0; i < ni; ++i) {
                    double d[8];
                    CornerEdges ce[8];
                    cornerJacobians(x, i, j, k, d, ce);
                    const double* gc = &g[b][8 * static_cast<std::size_t>(x.cell(i, j, k))];
                    for (int c = 0; c < 8; ++c) {
                        const double w = std::exp(-rho * (gc[c] - m)) / sum / d[c];
                        const double* e = ce[c].e[0];
                        const double* f = ce[c].e[1];
                        const double* h = ce[c].e[2];
                        const double grads[3][3] = {{f[1] * h[2] - f[2] * h[1], f[2] * h[0] - f[0] * h[2], f[0] * h[1] - f[1] * h[0]},
                                                    {h[1] * e[2] - h[2] * e[1], h[2] * e[0] - h[0] * e[2], h[0] * e[1] - h[1] * e[0]},
                                                    {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0]}};
                        for (int dd = 0; dd < 3; ++dd) {
                            for (int mm = 0; mm < 3; ++mm) {
                                out[3 * ce[c].to[dd] + mm] += w * grads[dd][mm];
                                out[3 * ce[c].from[dd] + mm] -= w * grads[dd][mm];
                            }
                        }
                    }
                }
            }
        }
    }
    return ks;
}

}  // namespace aero::mesh
