#pragma once
// Exact, shape-preserving knot insertion and refinement (Boehm; Piegl & Tiller A5.1), done
// in homogeneous coordinates so rational entities are preserved as well.
#include "nurbs/Surface.h"
#include "nurbs/Volume.h"

namespace aero::nurbs {

/// Inserts knot u `times` times (final multiplicity must stay <= degree). Throws GeometryError
/// if u lies outside the open parameter interval or the multiplicity would exceed the degree.
void insertKnot(Curve<double>& c, double u, int times = 1);
/// Inserts into direction dir (0 = u, 1 = v) of a surface.
void insertKnot(Surface<double>& s, int dir, double u, int times = 1);
/// Inserts into direction dir (0, 1, 2) of a volume.
void insertKnot(Volume<double>& v, int dir, double u, int times = 1);

/// Inserts every knot of `knots` (refinement), in any order.
void refine(Curve<double>& c, std::span<const double> knots);
void refine(Surface<double>& s, int dir, std::span<const double> knots);
void refine(Volume<double>& v, int dir, std::span<const double> knots);

/// Multiplicity of knot value u in a knot vector (exact comparison).
int multiplicity(std::span<const double> knots, double u);

}  // namespace aero::nurbs
