#pragma once
// The volume enclosed by a patch network and the symmetry plane Y = 0 (the paper's nonlinear
// constraint). By the divergence theorem V = 1/3 \oint x . n dA; on the plane Y = 0 the integrand
// x . n = -y vanishes, so only the patches contribute (the network must be closed by that plane,
// with normals pointing outward). Gauss-Legendre quadrature per knot cell: exact (to round-off)
// for polynomial patches.
#include <vector>

#include "geometry/PatchSet.h"

namespace aero::geometry {

/// Enclosed volume of the patches (any scalar type: complex step runs through it).
template <class T>
T enclosedVolume(const std::vector<nurbs::Surface<T>>& patches);

/// Throws GeometryError naming the patch when a patch is trimmed (the integral runs over whole
/// patches; integrating over trimmed regions is not implemented).
double enclosedVolume(const PatchSet& set);

/// dV/dA: 3 entries per (non-unique) control point, patches in order, u fastest.
std::vector<double> enclosedVolumeGradient(const PatchSet& set);

/// n Gauss-Legendre nodes and weights on [0, 1].
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace aero::geometry
