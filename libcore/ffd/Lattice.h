#pragma once
// FFD lattices (first level of the paper's two-level FFD): trivariate NURBS volumes whose
// control net B moves the embedded geometry control points (Section III.A).
#include <array>
#include <string>

#include "geometry/PatchSet.h"
#include "nurbs/Volume.h"

namespace aero::ffd {

using Lattice = nurbs::Volume<double>;

struct LatticeBox {
    std::array<double, 3> origin{0, 0, 0};  // corner at parameters (0, 0, 0)
    std::array<double, 3> size{1, 1, 1};    // edge lengths along the three axes
    // Orthonormal axes (rows): lattice direction d runs along axes[d]. Default: X, Y, Z.
    std::array<std::array<double, 3>, 3> axes{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
};

/// A lattice with `count` control points and degree `degree` per direction over `box`, uniform
/// clamped knots, control points at the Greville abscissae: the undeformed map is the affine
/// map of the box (linear precision), so embedding is well conditioned.
/// Throws GeometryError on counts < degree + 1, degrees outside [1, 9], or a degenerate box.
Lattice makeLattice(const LatticeBox& box, std::array<int, 3> count, std::array<int, 3> degree);

/// The box enclosing the control points of `set` (or only of `patches`, if not empty), in the
/// frame of `axes`, grown by `padding` (relative to the extent per direction; a flat direction
/// gets 1e-3 of the largest extent, so the box never degenerates). Zero padding puts a face
/// exactly on the extreme control points (e.g. on the symmetry plane Y = 0).
LatticeBox boxAround(const geometry::PatchSet& set, const std::vector<int>& patches,
                     std::array<double, 3> padding,
                     const std::array<std::array<double, 3>, 3>& axes = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});

/// Refines direction dir by inserting every knot of `knots` (the map and the embedding do not
/// change: embedded parameters stay valid).
void refineLattice(Lattice& lattice, int dir, std::span<const double> knots);

/// Makes the lattice C0 across the parameter plane dir = u by raising that knot's multiplicity
/// to the degree: a crease, e.g. to let a smooth shape form a sharp trailing edge.
void creaseLattice(Lattice& lattice, int dir, double u);

}  // namespace aero::ffd
