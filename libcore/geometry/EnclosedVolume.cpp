#include "geometry/EnclosedVolume.h"

#include <cmath>
#include <complex>
#include <numbers>

#include "common/Scalar.h"
#include "nurbs/Basis.h"

namespace aero::geometry {

using nurbs::Vec3;

namespace {

// P_n(z) and P_n'(z) by the three-term recurrence.
void legendre(int n, double z, double& p, double& dp) {
    double p0 = 1, p1 = z;
    for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    p = (n == 0) ? 1.0 : p1;
    dp = (n == 0) ? 0.0 : n * (z * p1 - p0) / (z * z - 1);
}

}  // namespace

void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
    x.resize(n);
    w.resize(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));  // initial guess
        double p = 0, dp = 0;
        for (int it = 0; it < 100; ++it) {
            legendre(n, z, p, dp);
            const double dz = p / dp;
            z -= dz;
            if (std::abs(dz) < 1e-16) break;
        }
        legendre(n, z, p, dp);
        x[i] = 0.5 * (1 - z);                 // mapped from [-1, 1] to [0, 1]
        w[i] = 1.0 / ((1 - z * z) * dp * dp);  // 2 / ((1 - z^2) P'^2), halved for [0, 1]
    }
}

namespace {

int quadratureOrder(int p, bool rational) {
    // Integrand degree 3p - 1 per direction for polynomial patches.
    return rational ? 2 * p + 4 : (3 * p) / 2 + 1;
}

// Visits every Gauss point of every knot cell: fn(su, sv, u, v, weight).
template <class S, class Fn>
void forEachQuadraturePoint(const S& s, Fn&& fn) {
    std::vector<double> gx, gw, hx, hw;
    gaussLegendre(quadratureOrder(s.degreeU, s.rational()), gx, gw);
    gaussLegendre(quadratureOrder(s.degreeV, s.rational()), hx, hw);
    for (int sv = s.degreeV; sv < s.countV; ++sv) {
        const double v0 = s.knotsV[sv], v1 = s.knotsV[sv + 1];
        if (!(v1 > v0)) continue;
        for (int su = s.degreeU; su < s.countU; ++su) {
            const double u0 = s.knotsU[su], u1 = s.knotsU[su + 1];
            if (!(u1 > u0)) continue;
            for (std::size_t b = 0; b < hx.size(); ++b) {
                for (std::size_t a = 0; a < gx.size(); ++a) {
                    fn(su, sv, u0 + (u1 - u0) * gx[a], v0 + (v1 - v0) * hx[b], gw[a] * hw[b] * (u1 - u0) * (v1 - v0));
                }
            }
        }
    }
}

}  // namespace

template <class T>
T enclosedVolume(const std::vector<nurbs::Surface<T>>& patches) {
    T vol = T(0.0);
    for (const auto& s : patches) {
        forEachQuadraturePoint(s, [&](int, int, double u, double v, double w) {
            const nurbs::SurfaceDerivatives<T> d = nurbs::evaluateDerivatives(s, T(u), T(v), 1);
            vol += T(w) * nurbs::plainDot<T>(d.S, nurbs::plainCross<T>(d.Su, d.Sv));
        });
    }
    return vol / T(3.0);
}

double enclosedVolume(const PatchSet& set) {
    requireUntrimmed(set, "the enclosed volume");
    return enclosedVolume<double>(set.patches);
}

std::vector<double> enclosedVolumeGradient(const PatchSet& set) {
    requireUntrimmed(set, "the enclosed volume");
    std::vector<double> g(3 * static_cast<std::size_t>(set.controlPointCount()), 0.0);
    std::size_t offset = 0;
    for (const Patch& s : set.patches) {
        const int p = s.degreeU, q = s.degreeV;
        forEachQuadraturePoint(s, [&](int su, int sv, double u, double v, double w) {
            double du[2 * (nurbs::kMaxDegree + 1)], dv[2 * (nurbs::kMaxDegree + 1)];
            nurbs::basisDerivatives(s.knotsU, p, su, u, 1, du);
            nurbs::basisDerivatives(s.knotsV, q, sv, v, 1, dv);
            // Weighted sums W, W_u, W_v for the rational basis R = N w / W.
            double W = 0, Wu = 0, Wv = 0;
            for (int j = 0; j <= q; ++j) {
                for (int i = 0; i <= p; ++i) {
                    const double wt = s.rational() ? s.weights[s.index(su - p + i, sv - q + j)] : 1.0;
                    W += du[i] * dv[j] * wt;
                    Wu += du[p + 1 + i] * dv[j] * wt;
                    Wv += du[i] * dv[q + 1 + j] * wt;
                }
            }
            const nurbs::SurfaceDerivatives<double> d = nurbs::evaluateDerivatives(s, u, v, 1);
            const Vec3<double> n = d.Su.cross(d.Sv), a = d.Sv.cross(d.S), b = d.S.cross(d.Su);
            for (int j = 0; j <= q; ++j) {
                for (int i = 0; i <= p; ++i) {
                    const int idx = s.index(su - p + i, sv - q + j);
                    const double wt = s.rational() ? s.weights[idx] : 1.0;
                    const double N = du[i] * dv[j] * wt, Nu = du[p + 1 + i] * dv[j] * wt, Nv = du[i] * dv[q + 1 + j] * wt;
                    const double R = N / W, Ru = (Nu * W - N * Wu) / (W * W), Rv = (Nv * W - N * Wv) / (W * W);
                    const Vec3<double> gi = (w / 3.0) * (R * n + Ru * a + Rv * b);
                    for (int c = 0; c < 3; ++c) g[offset + 3 * idx + c] += gi[c];
                }
            }
        });
        offset += s.points.size();
    }
    return g;
}

template double enclosedVolume(const std::vector<nurbs::Surface<double>>&);
template std::complex<double> enclosedVolume(const std::vector<nurbs::Surface<std::complex<double>>>&);

}  // namespace aero::geometry
