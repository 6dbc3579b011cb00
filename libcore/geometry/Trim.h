#pragma once
// Trimmed patches: the part of a patch's parameter rectangle that belongs to the body, bounded
// by closed loops of NURBS curves in the patch's own (u, v) space (IGES 144/142, STEP face
// bounds with their p-curves). The trims live in parameter space, so moving the patch's control
// points (FFD) keeps them exactly valid: the trimmed surface is S(trim region) for any S.
#include <array>
#include <string_view>
#include <vector>

#include "nurbs/Curve.h"
#include "nurbs/Surface.h"

namespace aero::geometry {

/// One piece of a loop: the part [first, last] of a NURBS curve in parameter space, traversed
/// from first to last. The curve's control points are (u, v, 0): the third coordinate is zero.
struct TrimCurve {
    nurbs::Curve<double> curve;
    double first = 0, last = 0;  // knots.front() <= first < last <= knots.back()
};

/// A closed loop: each curve's end is the next one's start, the last one ends at the first
/// one's start (within validate()'s tolerance).
struct TrimLoop {
    std::vector<TrimCurve> curves;
};

/// The kept region: inside `outer` (the whole parameter rectangle when `outer` has no curves)
/// and outside every hole. Loops keep the direction of the file they came from; which side is
/// inside is decided by the even-odd rule, so it does not depend on that direction.
struct PatchTrim {
    TrimLoop outer;
    std::vector<TrimLoop> holes;
    bool trimmed() const { return !outer.curves.empty() || !holes.empty(); }
};

using Point2 = std::array<double, 2>;

/// (u, v) of the trim curve at parameter t.
Point2 evaluate(const TrimCurve& c, double t);
Point2 startPoint(const TrimCurve& c);
Point2 endPoint(const TrimCurve& c);

/// The same piece traversed the other way, exactly: knots and range negated and reversed,
/// control points and weights reversed (negation is exact in floating point).
TrimCurve reversed(const TrimCurve& c);

/// A straight piece from a to b as a degree-1 curve on [0, 1] (control points a and b exactly).
TrimCurve lineCurve(const Point2& a, const Point2& b);
/// The rectangle [u0, u1] x [v0, v1] as four lines, counter-clockwise from (u0, v0).
TrimLoop rectangleLoop(double u0, double u1, double v0, double v1);

/// Whether every point of the loop lies on the boundary of the patch's parameter rectangle (its
/// knot range, to 1e-9 of its size; 9 samples per curve): an outer loop that trims nothing, as
/// some CAD systems write around every surface. The readers drop it (the patch is untrimmed).
bool onParameterBoundary(const TrimLoop& loop, const nurbs::Surface<double>& patch);

/// Largest gap between consecutive curve ends of a loop (including last -> first).
double closureGap(const TrimLoop& loop);

/// Throws GeometryError naming `what` (e.g. "patch 3 of 'wing.igs'") if a curve is invalid
/// (nurbs::validate, a non-zero third coordinate, a range outside its knots), a loop is not
/// closed or leaves the patch's parameter rectangle (both within 1e-6 of the rectangle's size).
/// Holes without an outer loop are allowed: they cut the whole rectangle.
void validate(const PatchTrim& trim, const nurbs::Surface<double>& patch, std::string_view what);

/// The loops as closed polygons in parameter space (outer first; the patch rectangle when the
/// outer loop is empty): `perSpan` points per non-empty knot span of each curve, at least 2 per
/// curve. The first point of a polygon is not repeated at its end.
struct TrimPolygons {
    std::vector<std::vector<Point2>> loops;
};
TrimPolygons polygonize(const PatchTrim& trim, const nurbs::Surface<double>& patch,
                        int perSpan = 16);

/// Whether (u, v) is in the kept region (even-odd rule over all loops). Points on a polygon edge
/// may go either way.
bool contains(const TrimPolygons& polygons, double u, double v);

/// Signed area of a loop's polygon in parameter space: positive when counter-clockwise.
double signedArea(const std::vector<Point2>& polygon);
/// Signed area enclosed by the loop's curves themselves (Green's theorem, 12-point Gauss-Legendre
/// per knot span: exact to round-off for polynomial curves up to degree 11).
double signedArea(const TrimLoop& loop);

}  // namespace aero::geometry
