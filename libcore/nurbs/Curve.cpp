#include "nurbs/Curve.h"

#include <complex>

#include "common/Scalar.h"
#include "nurbs/Basis.h"
#include "nurbs/Validate.h"

namespace aero::nurbs {

void validate(const Curve<double>& c, std::string_view what) {
    validateKnotVector(c.knots, c.degree, c.count(), what);
    detail::checkPointsAndWeights(c.points, c.weights, static_cast<std::size_t>(c.count()), what);
}

template <class T>
Vec3<T> evaluate(const Curve<T>& c, const T& u) {
    Vec3<T> out[1];
    evaluateDerivatives(c, u, 0, out);
    return out[0];
}

template <class T>
void evaluateDerivatives(const Curve<T>& c, const T& u, int nd, Vec3<T>* out) {
    const int p = c.degree;
    const int s = findSpan(c.knots, p, c.count(), realPart(u));
    T ders[3 * (kMaxDegree + 1)];
    basisDerivatives(c.knots, p, s, u, nd, ders);
    // Homogeneous derivatives A^(k) and w^(k).
    Vec3<T> A[3] = {Vec3<T>::Zero(), Vec3<T>::Zero(), Vec3<T>::Zero()};
    T w[3] = {T(0.0), T(0.0), T(0.0)};
    for (int k = 0; k <= nd; ++k) {
        for (int j = 0; j <= p; ++j) {
            const int idx = s - p + j;
            const T wj = c.rational() ? c.weights[idx] : T(1.0);
            const T f = ders[k * (p + 1) + j] * wj;
            A[k] += f * Vec3<T>(c.points[3 * idx], c.points[3 * idx + 1], c.points[3 * idx + 2]);
            w[k] += f;
        }
    }
    out[0] = A[0] / w[0];
    if (nd >= 1) out[1] = (A[1] - w[1] * out[0]) / w[0];
    if (nd >= 2) out[2] = (A[2] - T(2.0) * w[1] * out[1] - w[2] * out[0]) / w[0];
}

void evaluate(const Curve<double>& c, std::span<const double> u, double* out) {
    const long n = static_cast<long>(u.size());
#pragma omp parallel for schedule(static) if (n > 2048)
    for (long i = 0; i < n; ++i) {
        const Vec3<double> P = evaluate(c, u[i]);
        out[3 * i] = P[0];
        out[3 * i + 1] = P[1];
        out[3 * i + 2] = P[2];
    }
}

template Vec3<double> evaluate(const Curve<double>&, const double&);
template Vec3<std::complex<double>> evaluate(const Curve<std::complex<double>>&, const std::complex<double>&);
template void evaluateDerivatives(const Curve<double>&, const double&, int, Vec3<double>*);
template void evaluateDerivatives(const Curve<std::complex<double>>&, const std::complex<double>&, int,
                                  Vec3<std::complex<double>>*);

}  // namespace aero::nurbs
