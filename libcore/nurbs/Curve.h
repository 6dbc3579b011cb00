#pragma once
// NURBS curves: plain data plus free evaluation functions. Rational curves are evaluated in
// homogeneous coordinates (Eq. 1 of the paper) reusing the polynomial kernel.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products on Vec3
#include <span>
#include <vector>

namespace aero::nurbs {

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;

/// a . b and a x b without conjugation. For complex scalars Eigen's dot() conjugates its first
/// argument and cross() its result, which breaks complex-step differentiation: templated code
/// must use these.
template <class T>
T plainDot(const Vec3<T>& a, const Vec3<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
Vec3<T> plainCross(const Vec3<T>& a, const Vec3<T>& b) {
    return Vec3<T>(a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]);
}

/// A NURBS curve. points holds 3*count coordinates (x0,y0,z0,x1,...); weights is empty for
/// a polynomial B-spline or holds count positive weights.
template <class T>
struct Curve {
    int degree = 3;
    std::vector<double> knots;
    std::vector<T> points;
    std::vector<T> weights;

    int count() const { return static_cast<int>(points.size() / 3); }
    bool rational() const { return !weights.empty(); }
    double first() const { return knots.front(); }
    double last() const { return knots.back(); }
};

/// Throws GeometryError naming `what` if the knot vector, sizes, weights or coordinates
/// (NaN/inf) are invalid.
void validate(const Curve<double>& c, std::string_view what);

/// C(u).
template <class T>
Vec3<T> evaluate(const Curve<T>& c, const T& u);

/// C(u) and its derivatives up to order nd <= 2 into out[0..nd].
template <class T>
void evaluateDerivatives(const Curve<T>& c, const T& u, int nd, Vec3<T>* out);

/// Batched: out (3 x n, point-major) = C(u[i]). OpenMP over points; no allocation per point.
void evaluate(const Curve<double>& c, std::span<const double> u, double* out);

}  // namespace aero::nurbs
