#include "nurbs/Surface.h"

#include <complex>

#include "common/Scalar.h"
#include "nurbs/Basis.h"
#include "nurbs/Validate.h"

namespace aero::nurbs {

void validate(const Surface<double>& s, std::string_view what) {
    const std::string w(what);
    validateKnotVector(s.knotsU, s.degreeU, s.countU, w + " (u direction)");
    validateKnotVector(s.knotsV, s.degreeV, s.countV, w + " (v direction)");
    detail::checkPointsAndWeights(s.points, s.weights, static_cast<std::size_t>(s.controlCount()), what);
}

template <class T>
Vec3<T> evaluate(const Surface<T>& s, const T& u, const T& v) {
    const int p = s.degreeU, q = s.degreeV;
    const int su = findSpan(s.knotsU, p, s.countU, realPart(u));
    const int sv = findSpan(s.knotsV, q, s.countV, realPart(v));
    T Nu[kMaxDegree + 1], Nv[kMaxDegree + 1];
    basisFunctions(s.knotsU, p, su, u, Nu);
    basisFunctions(s.knotsV, q, sv, v, Nv);
    T a[4] = {T(0.0), T(0.0), T(0.0), T(0.0)};
    for (int l = 0; l <= q; ++l) {
        for (int k = 0; k <= p; ++k) {
            const int idx = s.index(su - p + k, sv - q + l);
            T f = Nu[k] * Nv[l];
            if (s.rational()) f *= s.weights[idx];
            a[0] += f * s.points[3 * idx];
            a[1] += f * s.points[3 * idx + 1];
            a[2] += f * s.points[3 * idx + 2];
            a[3] += f;
        }
    }
    return Vec3<T>(a[0] / a[3], a[1] / a[3], a[2] / a[3]);
}

template <class T>
SurfaceDerivatives<T> evaluateDerivatives(const Surface<T>& s, const T& u, const T& v, int nd) {
    const int p = s.degreeU, q = s.degreeV;
    const int su = findSpan(s.knotsU, p, s.countU, realPart(u));
    const int sv = findSpan(s.knotsV, q, s.countV, realPart(v));
    T du[3 * (kMaxDegree + 1)], dv[3 * (kMaxDegree + 1)];
    basisDerivatives(s.knotsU, p, su, u, nd, du);
    basisDerivatives(s.knotsV, q, sv, v, nd, dv);
    // Homogeneous derivatives H[k][l] = d^(k+l) (A, w) / du^k dv^l, k + l <= nd.
    Eigen::Matrix<T, 4, 1> H[3][3];
    for (int k = 0; k <= nd; ++k) {
        for (int l = 0; k + l <= nd; ++l) {
            H[k][l].setZero();
            for (int j = 0; j <= q; ++j) {
                for (int i = 0; i <= p; ++i) {
                    const int idx = s.index(su - p + i, sv - q + j);
                    T f = du[k * (p + 1) + i] * dv[l * (q + 1) + j];
                    if (s.rational()) f *= s.weights[idx];
                    H[k][l][0] += f * s.points[3 * idx];
                    H[k][l][1] += f * s.points[3 * idx + 1];
                    H[k][l][2] += f * s.points[3 * idx + 2];
                    H[k][l][3] += f;
                }
            }
        }
    }
    SurfaceDerivatives<T> d;
    auto A = [&](int k, int l) { return Vec3<T>(H[k][l].template head<3>()); };
    auto w = [&](int k, int l) { return H[k][l][3]; };
    const T w0 = w(0, 0);
    d.S = A(0, 0) / w0;
    d.Su.setZero();
    d.Sv.setZero();
    d.Suu.setZero();
    d.Suv.setZero();
    d.Svv.setZero();
    if (nd >= 1) {
        d.Su = (A(1, 0) - w(1, 0) * d.S) / w0;
        d.Sv = (A(0, 1) - w(0, 1) * d.S) / w0;
    }
    if (nd >= 2) {
        d.Suu = (A(2, 0) - T(2.0) * w(1, 0) * d.Su - w(2, 0) * d.S) / w0;
        d.Svv = (A(0, 2) - T(2.0) * w(0, 1) * d.Sv - w(0, 2) * d.S) / w0;
        d.Suv = (A(1, 1) - w(1, 0) * d.Sv - w(0, 1) * d.Su - w(1, 1) * d.S) / w0;
    }
    return d;
}

void evaluate(const Surface<double>& s, std::span<const double> uv, double* out) {
    const long n = static_cast<long>(uv.size() / 2);
#pragma omp parallel for schedule(static) if (n > 1024)
    for (long i = 0; i < n; ++i) {
        const Vec3<double> P = evaluate(s, uv[2 * i], uv[2 * i + 1]);
        out[3 * i] = P[0];
        out[3 * i + 1] = P[1];
        out[3 * i + 2] = P[2];
    }
}

void sampleGrid(const Surface<double>& s, std::span<const double> us, std::span<const double> vs,
                double* out) {
    const int p = s.degreeU, q = s.degreeV;
    const int nu = static_cast<int>(us.size()), nv = static_cast<int>(vs.size());
    // 1D basis rows, computed once per direction.
    std::vector<int> spanU(nu), spanV(nv);
    std::vector<double> Nu(static_cast<std::size_t>(nu) * (p + 1)), Nv(static_cast<std::size_t>(nv) * (q + 1));
    for (int a = 0; a < nu; ++a) {
        spanU[a] = findSpan(s.knotsU, p, s.countU, us[a]);
        basisFunctions(s.knotsU, p, spanU[a], us[a], &Nu[static_cast<std::size_t>(a) * (p + 1)]);
    }
    for (int b = 0; b < nv; ++b) {
        spanV[b] = findSpan(s.knotsV, q, s.countV, vs[b]);
        basisFunctions(s.knotsV, q, spanV[b], vs[b], &Nv[static_cast<std::size_t>(b) * (q + 1)]);
    }
    const bool rat = s.rational();
#pragma omp parallel if (static_cast<long>(nu) * nv > 4096)
    {
        std::vector<double> row(4 * static_cast<std::size_t>(s.countU));  // per thread, reused
#pragma omp for schedule(static)
        for (int b = 0; b < nv; ++b) {
            // Contract the v direction: row[i] = sum_l Nv[l] * Pw(i, sv - q + l).
            const double* N = &Nv[static_cast<std::size_t>(b) * (q + 1)];
            std::fill(row.begin(), row.end(), 0.0);
            for (int l = 0; l <= q; ++l) {
                const int j = spanV[b] - q + l;
                for (int i = 0; i < s.countU; ++i) {
                    const int idx = s.index(i, j);
                    const double f = rat ? N[l] * s.weights[idx] : N[l];
                    row[4 * i] += f * s.points[3 * idx];
                    row[4 * i + 1] += f * s.points[3 * idx + 1];
                    row[4 * i + 2] += f * s.points[3 * idx + 2];
                    row[4 * i + 3] += f;
                }
            }
            // Contract the u direction.
            for (int a = 0; a < nu; ++a) {
                const double* M = &Nu[static_cast<std::size_t>(a) * (p + 1)];
                double x = 0, y = 0, z = 0, w = 0;
                for (int k = 0; k <= p; ++k) {
                    const double* r = &row[4 * (spanU[a] - p + k)];
                    x += M[k] * r[0];
                    y += M[k] * r[1];
                    z += M[k] * r[2];
                    w += M[k] * r[3];
                }
                double* o = out + 3 * (static_cast<std::size_t>(b) * nu + a);
                o[0] = x / w;
                o[1] = y / w;
                o[2] = z / w;
            }
        }
    }
}

Curve<double> boundaryCurve(const Surface<double>& s, int edge) {
    Curve<double> c;
    const bool alongU = (edge == 0 || edge == 2);
    c.degree = alongU ? s.degreeU : s.degreeV;
    c.knots = alongU ? s.knotsU : s.knotsV;
    const int n = alongU ? s.countU : s.countV;
    c.points.resize(3 * static_cast<std::size_t>(n));
    if (s.rational()) c.weights.resize(n);
    for (int t = 0; t < n; ++t) {
        int idx = 0;
        switch (edge) {
            case 0: idx = s.index(t, 0); break;
            case 1: idx = s.index(s.countU - 1, t); break;
            case 2: idx = s.index(t, s.countV - 1); break;
            default: idx = s.index(0, t); break;
        }
        for (int d = 0; d < 3; ++d) c.points[3 * t + d] = s.points[3 * idx + d];
        if (s.rational()) c.weights[t] = s.weights[idx];
    }
    return c;
}

template Vec3<double> evaluate(const Surface<double>&, const double&, const double&);
template Vec3<std::complex<double>> evaluate(const Surface<std::complex<double>>&, const std::complex<double>&,
                                             const std::complex<double>&);
template SurfaceDerivatives<double> evaluateDerivatives(const Surface<double>&, const double&, const double&, int);
template SurfaceDerivatives<std::complex<double>> evaluateDerivatives(const Surface<std::complex<double>>&,
                                                                      const std::complex<double>&,
                                                                      const std::complex<double>&, int);

}  // namespace aero::nurbs
