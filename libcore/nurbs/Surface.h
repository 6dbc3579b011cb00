#pragma once
// NURBS surfaces (patches). Control net layout: index (i, j) -> i + countU * j, u fastest,
// the same order as IGES entity 128.
#include "nurbs/Curve.h"

namespace aero::nurbs {

template <class T>
struct Surface {
    int degreeU = 3, degreeV = 3;
    int countU = 0, countV = 0;
    std::vector<double> knotsU, knotsV;
    std::vector<T> points;   // 3 * countU * countV
    std::vector<T> weights;  // empty or countU * countV

    bool rational() const { return !weights.empty(); }
    int controlCount() const { return countU * countV; }
    int index(int i, int j) const { return i + countU * j; }
};

/// S and its first and second partial derivatives.
template <class T>
struct SurfaceDerivatives {
    Vec3<T> S, Su, Sv, Suu, Suv, Svv;
};

/// Throws GeometryError naming `what` on bad knots, sizes, weights or non-finite coordinates.
void validate(const Surface<double>& s, std::string_view what);

template <class T>
Vec3<T> evaluate(const Surface<T>& s, const T& u, const T& v);

/// Derivatives up to order nd (1 or 2; second-order members are left zero for nd = 1).
template <class T>
SurfaceDerivatives<T> evaluateDerivatives(const Surface<T>& s, const T& u, const T& v, int nd);

/// Batched: uv holds n (u, v) pairs interleaved; out (3 x n) = S(u_i, v_i). OpenMP over points.
void evaluate(const Surface<double>& s, std::span<const double> uv, double* out);

/// Structured sampling on the tensor grid us x vs by the separable form (1D basis rows
/// precomputed once per direction). out has 3 * us.size() * vs.size() entries, u fastest.
void sampleGrid(const Surface<double>& s, std::span<const double> us, std::span<const double> vs,
                double* out);

/// Boundary curve of a surface: edge 0: v = v0, 1: u = u1, 2: v = v1, 3: u = u0,
/// each parameterized in the direction of increasing u (edges 0, 2) or v (edges 1, 3).
Curve<double> boundaryCurve(const Surface<double>& s, int edge);

}  // namespace aero::nurbs
