#include "nurbs/Volume.h"

#include <algorithm>
#include <complex>

#include "common/Scalar.h"
#include "nurbs/Basis.h"
#include "nurbs/Validate.h"

namespace aero::nurbs {

void validate(const Volume<double>& v, std::string_view what) {
    static const char* dirName[3] = {" (xi direction)", " (eta direction)", " (zeta direction)"};
    for (int d = 0; d < 3; ++d) {
        validateKnotVector(v.knots[d], v.degree[d], v.count[d], std::string(what) + dirName[d]);
    }
    detail::checkPointsAndWeights(v.points, v.weights, static_cast<std::size_t>(v.controlCount()), what);
}

template <class T>
Vec3<T> evaluate(const Volume<T>& v, const T& xi, const T& eta, const T& zeta) {
    Vec3<T> P;
    Eigen::Matrix<T, 3, 3> J;
    evaluateJacobian(v, xi, eta, zeta, P, J);
    return P;
}

template <class T>
void evaluateJacobian(const Volume<T>& v, const T& xi, const T& eta, const T& zeta, Vec3<T>& P,
                      Eigen::Matrix<T, 3, 3>& J) {
    const T par[3] = {xi, eta, zeta};
    int span[3];
    T d[3][2 * (kMaxDegree + 1)];
    for (int c = 0; c < 3; ++c) {
        span[c] = findSpan(v.knots[c], v.degree[c], v.count[c], realPart(par[c]));
        basisDerivatives(v.knots[c], v.degree[c], span[c], par[c], 1, d[c]);
    }
    const int p0 = v.degree[0], p1 = v.degree[1], p2 = v.degree[2];
    // Homogeneous value (H[0]) and first derivatives (H[1..3]) of (A, w).
    Eigen::Matrix<T, 4, 1> H[4];
    for (auto& h : H) h.setZero();
    for (int k = 0; k <= p2; ++k) {
        for (int j = 0; j <= p1; ++j) {
            for (int i = 0; i <= p0; ++i) {
                const int idx = v.index(span[0] - p0 + i, span[1] - p1 + j, span[2] - p2 + k);
                const T w = v.rational() ? v.weights[idx] : T(1.0);
                const T n0 = d[0][i], n1 = d[1][j], n2 = d[2][k];
                const T f[4] = {n0 * n1 * n2, d[0][p0 + 1 + i] * n1 * n2, n0 * d[1][p1 + 1 + j] * n2,
                                n0 * n1 * d[2][p2 + 1 + k]};
                const Eigen::Matrix<T, 4, 1> Bw(w * v.points[3 * idx], w * v.points[3 * idx + 1],
                                                w * v.points[3 * idx + 2], w);
                for (int m = 0; m < 4; ++m) H[m] += f[m] * Bw;
            }
        }
    }
    const T w0 = H[0][3];
    P = H[0].template head<3>() / w0;
    for (int c = 0; c < 3; ++c) {
        J.col(c) = (H[c + 1].template head<3>() - H[c + 1][3] * P) / w0;
    }
}

void evaluate(const Volume<double>& v, std::span<const double> params, double* out) {
    const long n = static_cast<long>(params.size() / 3);
#pragma omp parallel for schedule(static) if (n > 1024)
    for (long i = 0; i < n; ++i) {
        const Vec3<double> P = evaluate(v, params[3 * i], params[3 * i + 1], params[3 * i + 2]);
        out[3 * i] = P[0];
        out[3 * i + 1] = P[1];
        out[3 * i + 2] = P[2];
    }
}

int basisAt(const Volume<double>& v, const double* xi, int* idx, double* val) {
    int span[3];
    double N[3][kMaxDegree + 1];
    for (int c = 0; c < 3; ++c) {
        span[c] = findSpan(v.knots[c], v.degree[c], v.count[c], xi[c]);
        basisFunctions(v.knots[c], v.degree[c], span[c], xi[c], N[c]);
    }
    int n = 0;
    double sum = 0;
    for (int k = 0; k <= v.degree[2]; ++k) {
        for (int j = 0; j <= v.degree[1]; ++j) {
            for (int i = 0; i <= v.degree[0]; ++i) {
                const int a = v.index(span[0] - v.degree[0] + i, span[1] - v.degree[1] + j,
                                      span[2] - v.degree[2] + k);
                double f = N[0][i] * N[1][j] * N[2][k];
                if (v.rational()) f *= v.weights[a];
                idx[n] = a;
                val[n] = f;
                sum += f;
                ++n;
            }
        }
    }
    if (v.rational()) {
        for (int m = 0; m < n; ++m) val[m] /= sum;
    }
    return n;
}

namespace {

struct BasisRows {
    std::vector<int> span;
    std::vector<double> N;  // (p + 1) per sample
    int p = 0;
    const double* row(int a) const { return &N[static_cast<std::size_t>(a) * (p + 1)]; }
};

BasisRows basisRows(const Volume<double>& v, int dir, std::span<const double> s) {
    BasisRows r;
    r.p = v.degree[dir];
    r.span.resize(s.size());
    r.N.resize(s.size() * (r.p + 1));
    for (std::size_t a = 0; a < s.size(); ++a) {
        r.span[a] = findSpan(v.knots[dir], r.p, v.count[dir], s[a]);
        basisFunctions(v.knots[dir], r.p, r.span[a], s[a], &r.N[a * (r.p + 1)]);
    }
    return r;
}

// Sum factorization with NC components per control point (3: polynomial, 4: homogeneous).
template <int NC>
void sampleGridImpl(const Volume<double>& v, const BasisRows& R0, const BasisRows& R1, const BasisRows& R2,
                    double* out) {
    const int n0 = v.count[0], n1 = v.count[1];
    const int m0 = static_cast<int>(R0.span.size()), m1 = static_cast<int>(R1.span.size());
    const int m2 = static_cast<int>(R2.span.size());
    // Control net in (weighted) homogeneous form, NC components, layout [k][j][i][c].
    std::vector<double> Pw(static_cast<std::size_t>(v.controlCount()) * NC);
    for (int a = 0; a < v.controlCount(); ++a) {
        const double w = (NC == 4) ? v.weights[a] : 1.0;
        for (int c = 0; c < 3; ++c) Pw[NC * a + c] = w * v.points[3 * a + c];
        if (NC == 4) Pw[NC * a + 3] = w;
    }
#pragma omp parallel if (static_cast<long>(m0) * m1 * m2 > 8192)
    {
        // Per-thread work arrays, allocated once.
        std::vector<double> T1(static_cast<std::size_t>(n1) * n0 * NC);  // [j][i][c] at one zeta
        std::vector<double> T2(static_cast<std::size_t>(m1) * n0 * NC);  // [b][i][c]
#pragma omp for schedule(static)
        for (int c2 = 0; c2 < m2; ++c2) {
            // Contract zeta.
            std::fill(T1.begin(), T1.end(), 0.0);
            const double* N2 = R2.row(c2);
            for (int l = 0; l <= R2.p; ++l) {
                const double f = N2[l];
                const double* src = &Pw[static_cast<std::size_t>(R2.span[c2] - R2.p + l) * n1 * n0 * NC];
#pragma omp simd
                for (int t = 0; t < n1 * n0 * NC; ++t) T1[t] += f * src[t];
            }
            // Contract eta.
            for (int b = 0; b < m1; ++b) {
                double* dst = &T2[static_cast<std::size_t>(b) * n0 * NC];
                std::fill(dst, dst + n0 * NC, 0.0);
                const double* N1 = R1.row(b);
                for (int l = 0; l <= R1.p; ++l) {
                    const double f = N1[l];
                    const double* src = &T1[static_cast<std::size_t>(R1.span[b] - R1.p + l) * n0 * NC];
#pragma omp simd
                    for (int t = 0; t < n0 * NC; ++t) dst[t] += f * src[t];
                }
            }
            // Contract xi and project.
            for (int b = 0; b < m1; ++b) {
                const double* row = &T2[static_cast<std::size_t>(b) * n0 * NC];
                double* o = out + 3 * (static_cast<std::size_t>(c2) * m1 + b) * m0;
                for (int a = 0; a < m0; ++a) {
                    const double* N0 = R0.row(a);
                    const double* src = row + static_cast<std::size_t>(R0.span[a] - R0.p) * NC;
                    double acc[NC] = {};
                    for (int k = 0; k <= R0.p; ++k) {
                        for (int c = 0; c < NC; ++c) acc[c] += N0[k] * src[k * NC + c];
                    }
                    const double inv = (NC == 4) ? 1.0 / acc[NC - 1] : 1.0;
                    o[3 * a] = acc[0] * inv;
                    o[3 * a + 1] = acc[1] * inv;
                    o[3 * a + 2] = acc[2] * inv;
                }
            }
        }
    }
}

}  // namespace

void sampleGrid(const Volume<double>& v, std::span<const double> s0, std::span<const double> s1,
                std::span<const double> s2, double* out) {
    const BasisRows R0 = basisRows(v, 0, s0), R1 = basisRows(v, 1, s1), R2 = basisRows(v, 2, s2);
    if (v.rational()) {
        sampleGridImpl<4>(v, R0, R1, R2, out);
    } else {
        sampleGridImpl<3>(v, R0, R1, R2, out);
    }
}

template Vec3<double> evaluate(const Volume<double>&, const double&, const double&, const double&);
template Vec3<std::complex<double>> evaluate(const Volume<std::complex<double>>&, const std::complex<double>&,
                                             const std::complex<double>&, const std::complex<double>&);
template void evaluateJacobian(const Volume<double>&, const double&, const double&, const double&,
                               Vec3<double>&, Eigen::Matrix<double, 3, 3>&);
template void evaluateJacobian(const Volume<std::complex<double>>&, const std::complex<double>&,
                               const std::complex<double>&, const std::complex<double>&,
                               Vec3<std::complex<double>>&, Eigen::Matrix<std::complex<double>, 3, 3>&);

}  // namespace aero::nurbs
