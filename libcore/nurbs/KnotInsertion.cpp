#include "nurbs/KnotInsertion.h"

#include <sstream>

#include "common/Error.h"
#include "nurbs/Basis.h"

namespace aero::nurbs {

int multiplicity(std::span<const double> knots, double u) {
    int m = 0;
    for (double k : knots) m += (k == u) ? 1 : 0;
    return m;
}

namespace {

// A control net seen along one direction: control point (t, inner, outer) lives at
// inner + innerSize * (t + n * outer). Coordinates are homogeneous (wx, wy, wz, w).
struct StridedNet {
    std::vector<double> Pw;  // 4 per control point
    int n = 0, innerSize = 1, outerSize = 1;
    std::size_t at(int t, int in, int out) const {
        return 4 * (static_cast<std::size_t>(in) + static_cast<std::size_t>(innerSize) *
                                                     (static_cast<std::size_t>(t) + static_cast<std::size_t>(n) * out));
    }
};

StridedNet toHomogeneous(const std::vector<double>& points, const std::vector<double>& weights, int n,
                         int innerSize, int outerSize) {
    StridedNet net;
    net.n = n;
    net.innerSize = innerSize;
    net.outerSize = outerSize;
    const std::size_t count = points.size() / 3;
    net.Pw.resize(4 * count);
    for (std::size_t a = 0; a < count; ++a) {
        const double w = weights.empty() ? 1.0 : weights[a];
        for (int c = 0; c < 3; ++c) net.Pw[4 * a + c] = w * points[3 * a + c];
        net.Pw[4 * a + 3] = w;
    }
    return net;
}

void fromHomogeneous(const StridedNet& net, std::vector<double>& points, std::vector<double>& weights) {
    const std::size_t count = net.Pw.size() / 4;
    const bool rational = !weights.empty();
    points.resize(3 * count);
    if (rational) weights.resize(count);
    for (std::size_t a = 0; a < count; ++a) {
        const double w = net.Pw[4 * a + 3];
        for (int c = 0; c < 3; ++c) points[3 * a + c] = rational ? net.Pw[4 * a + c] / w : net.Pw[4 * a + c];
        if (rational) weights[a] = w;
    }
}

// One insertion of u into (degree p, knots U) on the strided net (Boehm's algorithm).
void insertOnce(int p, std::vector<double>& U, StridedNet& net, double u) {
    const int k = findSpan(U, p, net.n, u);
    const int s = multiplicity(U, u);
    StridedNet q;
    q.n = net.n + 1;
    q.innerSize = net.innerSize;
    q.outerSize = net.outerSize;
    q.Pw.resize(static_cast<std::size_t>(q.n) * net.innerSize * net.outerSize * 4);
    for (int out = 0; out < net.outerSize; ++out) {
        for (int in = 0; in < net.innerSize; ++in) {
            for (int t = 0; t < q.n; ++t) {
                double* dst = &q.Pw[q.at(t, in, out)];
                if (t <= k - p) {
                    const double* a = &net.Pw[net.at(t, in, out)];
                    for (int c = 0; c < 4; ++c) dst[c] = a[c];
                } else if (t >= k - s + 1) {
                    const double* a = &net.Pw[net.at(t - 1, in, out)];
                    for (int c = 0; c < 4; ++c) dst[c] = a[c];
                } else {
                    const double alpha = (u - U[t]) / (U[t + p] - U[t]);
                    const double* a = &net.Pw[net.at(t, in, out)];
                    const double* b = &net.Pw[net.at(t - 1, in, out)];
                    for (int c = 0; c < 4; ++c) dst[c] = alpha * a[c] + (1.0 - alpha) * b[c];
                }
            }
        }
    }
    U.insert(U.begin() + k + 1, u);
    net = std::move(q);
}

void checkInsertion(const std::vector<double>& U, int p, double u, int times) {
    if (!(u > U.front() && u < U.back())) {
        std::ostringstream m;
        m.precision(17);
        m << "knot insertion: " << u << " is outside the open parameter interval (" << U.front() << ", "
          << U.back() << ")";
        throw GeometryError(m.str());
    }
    if (times < 0 || multiplicity(U, u) + times > p) {
        std::ostringstream m;
        m.precision(17);
        m << "knot insertion: inserting " << u << " " << times << " time(s) would raise its multiplicity to "
          << multiplicity(U, u) + times << ", above the degree " << p;
        throw GeometryError(m.str());
    }
}

}  // namespace

void insertKnot(Curve<double>& c, double u, int times) {
    checkInsertion(c.knots, c.degree, u, times);
    StridedNet net = toHomogeneous(c.points, c.weights, c.count(), 1, 1);
    for (int r = 0; r < times; ++r) insertOnce(c.degree, c.knots, net, u);
    fromHomogeneous(net, c.points, c.weights);
}

void insertKnot(Surface<double>& s, int dir, double u, int times) {
    auto& U = dir == 0 ? s.knotsU : s.knotsV;
    const int p = dir == 0 ? s.degreeU : s.degreeV;
    checkInsertion(U, p, u, times);
    StridedNet net = dir == 0 ? toHomogeneous(s.points, s.weights, s.countU, 1, s.countV)
                              : toHomogeneous(s.points, s.weights, s.countV, s.countU, 1);
    for (int r = 0; r < times; ++r) insertOnce(p, U, net, u);
    fromHomogeneous(net, s.points, s.weights);
    (dir == 0 ? s.countU : s.countV) += times;
}

void insertKnot(Volume<double>& v, int dir, double u, int times) {
    checkInsertion(v.knots[dir], v.degree[dir], u, times);
    int inner = 1, outer = 1;
    for (int d = 0; d < dir; ++d) inner *= v.count[d];
    for (int d = dir + 1; d < 3; ++d) outer *= v.count[d];
    StridedNet net = toHomogeneous(v.points, v.weights, v.count[dir], inner, outer);
    for (int r = 0; r < times; ++r) insertOnce(v.degree[dir], v.knots[dir], net, u);
    fromHomogeneous(net, v.points, v.weights);
    v.count[dir] += times;
}

void refine(Curve<double>& c, std::span<const double> knots) {
    for (double u : knots) insertKnot(c, u, 1);
}
void refine(Surface<double>& s, int dir, std::span<const double> knots) {
    for (double u : knots) insertKnot(s, dir, u, 1);
}
void refine(Volume<double>& v, int dir, std::span<const double> knots) {
    for (double u : knots) insertKnot(v, dir, u, 1);
}

}  // namespace aero::nurbs
