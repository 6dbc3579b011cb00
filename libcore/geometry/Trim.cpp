#include "geometry/Trim.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "common/Error.h"
#include "geometry/EnclosedVolume.h"

namespace aero::geometry {

Point2 evaluate(const TrimCurve& c, double t) {
    const nurbs::Vec3<double> p = nurbs::evaluate(c.curve, t);
    return {p.x(), p.y()};
}

Point2 startPoint(const TrimCurve& c) {
    return evaluate(c, c.first);
}
Point2 endPoint(const TrimCurve& c) {
    return evaluate(c, c.last);
}

TrimCurve reversed(const TrimCurve& c) {
    TrimCurve r;
    r.curve.degree = c.curve.degree;
    r.curve.knots.assign(c.curve.knots.rbegin(), c.curve.knots.rend());
    for (double& k : r.curve.knots) k = -k;
    const int n = c.curve.count();
    r.curve.points.resize(c.curve.points.size());
    for (int i = 0; i < n; ++i)
        for (int d = 0; d < 3; ++d) r.curve.points[3 * i + d] = c.curve.points[3 * (n - 1 - i) + d];
    r.curve.weights.assign(c.curve.weights.rbegin(), c.curve.weights.rend());
    r.first = -c.last;
    r.last = -c.first;
    return r;
}

TrimCurve lineCurve(const Point2& a, const Point2& b) {
    TrimCurve c;
    c.curve.degree = 1;
    c.curve.knots = {0.0, 0.0, 1.0, 1.0};
    c.curve.points = {a[0], a[1], 0.0, b[0], b[1], 0.0};
    c.first = 0.0;
    c.last = 1.0;
    return c;
}

TrimLoop rectangleLoop(double u0, double u1, double v0, double v1) {
    TrimLoop loop;
    loop.curves = {lineCurve({u0, v0}, {u1, v0}), lineCurve({u1, v0}, {u1, v1}),
                   lineCurve({u1, v1}, {u0, v1}), lineCurve({u0, v1}, {u0, v0})};
    return loop;
}

bool onParameterBoundary(const TrimLoop& loop, const nurbs::Surface<double>& patch) {
    const double u0 = patch.knotsU.front(), u1 = patch.knotsU.back(), v0 = patch.knotsV.front(),
                 v1 = patch.knotsV.back();
    const double tol = 1e-9 * std::max(u1 - u0, v1 - v0);
    for (const TrimCurve& c : loop.curves)
        for (int k = 0; k <= 8; ++k) {
            const Point2 uv = evaluate(c, c.first + (c.last - c.first) * k / 8);
            const bool edge = std::abs(uv[0] - u0) <= tol || std::abs(uv[0] - u1) <= tol ||
                              std::abs(uv[1] - v0) <= tol || std::abs(uv[1] - v1) <= tol;
            if (!edge) return false;
        }
    return true;
}

double closureGap(const TrimLoop& loop) {
    double gap = 0;
    const std::size_t n = loop.curves.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Point2 a = endPoint(loop.curves[i]), b = startPoint(loop.curves[(i + 1) % n]);
        gap = std::max(gap, std::hypot(a[0] - b[0], a[1] - b[1]));
    }
    return gap;
}

namespace {

struct Domain {
    double u0, u1, v0, v1;
    double size() const { return std::max(u1 - u0, v1 - v0); }
};

Domain domainOf(const nurbs::Surface<double>& s) {
    return {s.knotsU[static_cast<std::size_t>(s.degreeU)],
            s.knotsU[static_cast<std::size_t>(s.countU)],
            s.knotsV[static_cast<std::size_t>(s.degreeV)],
            s.knotsV[static_cast<std::size_t>(s.countV)]};
}

std::string number(double x) {
    std::ostringstream s;
    s.precision(6);
    s << x;
    return s.str();
}

/// Appends the polygon of one curve (without its last point, which starts the next curve).
void appendPolygon(const TrimCurve& c, int perSpan, std::vector<Point2>& out) {
    std::vector<double> breaks{c.first};
    for (double k : c.curve.knots)
        if (k > breaks.back() && k < c.last) breaks.push_back(k);
    breaks.push_back(c.last);
    const int per = std::max(1, perSpan);
    for (std::size_t s = 0; s + 1 < breaks.size(); ++s)
        for (int i = 0; i < per; ++i)
            out.push_back(evaluate(c, breaks[s] + (breaks[s + 1] - breaks[s]) * i / per));
}

std::vector<Point2> loopPolygon(const TrimLoop& loop, int perSpan) {
    std::vector<Point2> poly;
    for (const TrimCurve& c : loop.curves) appendPolygon(c, perSpan, poly);
    return poly;
}

}  // namespace

void validate(const PatchTrim& trim, const nurbs::Surface<double>& patch, std::string_view what) {
    const Domain d = domainOf(patch);
    const double tol = 1e-6 * d.size();
    auto check = [&](const TrimLoop& loop, const std::string& name) {
        const std::string where = std::string(what) + ", " + name;
        if (loop.curves.empty()) throw GeometryError(where + ": has no curves");
        for (std::size_t k = 0; k < loop.curves.size(); ++k) {
            const TrimCurve& c = loop.curves[k];
            const std::string cw = where + " curve " + std::to_string(k + 1);
            nurbs::validate(c.curve, cw);
            for (std::size_t a = 2; a < c.curve.points.size(); a += 3)
                if (c.curve.points[a] != 0.0)
                    throw GeometryError(cw + ": control point " + std::to_string(a / 3) +
                                        " has a third coordinate " + number(c.curve.points[a]) +
                                        " (parameter-space curves lie in the (u, v) plane)");
            if (!(c.first < c.last) || c.first < c.curve.first() || c.last > c.curve.last())
                throw GeometryError(cw + ": range [" + number(c.first) + ", " + number(c.last) +
                                    "] is empty or outside the curve's knots [" +
                                    number(c.curve.first()) + ", " + number(c.curve.last()) + "]");
        }
        if (const double gap = closureGap(loop); !(gap <= tol))
            throw GeometryError(where + ": not closed (a gap of " + number(gap) +
                                " between consecutive curves in " + "parameter space, more than " +
                                number(tol) + ")");
        for (const Point2& p : loopPolygon(loop, 4))
            if (p[0] < d.u0 - tol || p[0] > d.u1 + tol || p[1] < d.v0 - tol || p[1] > d.v1 + tol)
                throw GeometryError(where + ": leaves the patch's parameter rectangle [" +
                                    number(d.u0) + ", " + number(d.u1) + "] x [" + number(d.v0) +
                                    ", " + number(d.v1) + "] at (" + number(p[0]) + ", " +
                                    number(p[1]) + ")");
    };
    if (!trim.outer.curves.empty()) check(trim.outer, "outer trim loop");
    for (std::size_t h = 0; h < trim.holes.size(); ++h)
        check(trim.holes[h], "trim hole " + std::to_string(h + 1));
}

TrimPolygons polygonize(const PatchTrim& trim, const nurbs::Surface<double>& patch, int perSpan) {
    TrimPolygons out;
    if (trim.outer.curves.empty()) {
        const Domain d = domainOf(patch);
        out.loops.push_back({{d.u0, d.v0}, {d.u1, d.v0}, {d.u1, d.v1}, {d.u0, d.v1}});
    } else {
        out.loops.push_back(loopPolygon(trim.outer, perSpan));
    }
    for (const TrimLoop& h : trim.holes) out.loops.push_back(loopPolygon(h, perSpan));
    return out;
}

bool contains(const TrimPolygons& polygons, double u, double v) {
    bool inside = false;
    for (const auto& poly : polygons.loops) {
        const std::size_t n = poly.size();
        for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
            const Point2& a = poly[i];
            const Point2& b = poly[j];
            if ((a[1] > v) != (b[1] > v)) {
                const double uCross = a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if (u < uCross) inside = !inside;
            }
        }
    }
    return inside;
}

double signedArea(const std::vector<Point2>& polygon) {
    double a = 0;
    const std::size_t n = polygon.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++)
        a += polygon[j][0] * polygon[i][1] - polygon[i][0] * polygon[j][1];
    return 0.5 * a;
}

double signedArea(const TrimLoop& loop) {
    std::vector<double> x, w;
    gaussLegendre(12, x, w);
    double a = 0;
    for (const TrimCurve& c : loop.curves) {
        std::vector<double> breaks{c.first};
        for (double k : c.curve.knots)
            if (k > breaks.back() && k < c.last) breaks.push_back(k);
        breaks.push_back(c.last);
        for (std::size_t s = 0; s + 1 < breaks.size(); ++s) {
            const double h = breaks[s + 1] - breaks[s];
            for (std::size_t q = 0; q < x.size(); ++q) {
                nurbs::Vec3<double> d[2];
                nurbs::evaluateDerivatives(c.curve, breaks[s] + h * x[q], 1, d);
                a += 0.5 * w[q] * h * (d[0].x() * d[1].y() - d[0].y() * d[1].x());
            }
        }
    }
    return a;
}

}  // namespace aero::geometry
