#pragma once
// Trivariate NURBS volumes (Eq. 2 of the paper). Control net layout [k][j][i][xyz]:
// index (i, j, k) -> i + count[0] * (j + count[1] * k).
#include <array>

#include "nurbs/Curve.h"

namespace aero::nurbs {

template <class T>
struct Volume {
    std::array<int, 3> degree{3, 3, 3};
    std::array<int, 3> count{0, 0, 0};
    std::array<std::vector<double>, 3> knots;
    std::vector<T> points;   // 3 * count[0] * count[1] * count[2]
    std::vector<T> weights;  // empty or one per control point

    bool rational() const { return !weights.empty(); }
    int controlCount() const { return count[0] * count[1] * count[2]; }
    int index(int i, int j, int k) const { return i + count[0] * (j + count[1] * k); }
};

/// Throws GeometryError naming `what` on bad knots, sizes, weights or non-finite coordinates.
void validate(const Volume<double>& v, std::string_view what);

template <class T>
Vec3<T> evaluate(const Volume<T>& v, const T& xi, const T& eta, const T& zeta);

/// V(xi) and its Jacobian J(r, c) = dV_r / dxi_c.
template <class T>
void evaluateJacobian(const Volume<T>& v, const T& xi, const T& eta, const T& zeta, Vec3<T>& P,
                      Eigen::Matrix<T, 3, 3>& J);

/// Batched: params holds n (xi, eta, zeta) triples; out (3 x n). OpenMP over points.
void evaluate(const Volume<double>& v, std::span<const double> params, double* out);

/// The rational basis values R_a(xi) that are non-zero at xi and their control-point indices a:
/// V(xi) = sum_a R_a B_a, which is also dV/dB_a (Eq. 3). Returns the number written
/// (at most prod(degree+1)); idx and val need that much room.
int basisAt(const Volume<double>& v, const double* xi, int* idx, double* val);

/// Structured sampling on the tensor grid s0 x s1 x s2 by sum factorization: 1D basis rows
/// per direction, contracted one direction at a time (cost ~ 3*(p+1) flops per output
/// point instead of 3*(p+1)^3). out has 3 * |s0| * |s1| * |s2| entries, layout [k][j][i][xyz].
void sampleGrid(const Volume<double>& v, std::span<const double> s0, std::span<const double> s1,
                std::span<const double> s2, double* out);

}  // namespace aero::nurbs
