#pragma once
// Pointwise physics of the 3D Euler equations, templated on the scalar type (double for the
// solver, std::complex<double> for complex-step derivatives).
//
// Nondimensionalization (used everywhere in libcore/flow): density by the free-stream density
// rho_inf, velocity by the free-stream speed of sound a_inf, pressure and energy per volume by
// rho_inf a_inf^2, lengths by the grid's unit. So rho_inf = 1, |u_inf| = Mach, p_inf = 1/gamma,
// a_inf = 1, and the dynamic pressure is Mach^2 / 2.
//
// State q (5 values): conservative (rho, rho u, rho v, rho w, rho E). A "normal" n (3 values) is
// never normalized: it is a metric vector (e.g. grad(xi)/J), so fluxes and Jacobians scale with |n|.
#include <array>
#include <cmath>
#include <complex>

#include "common/Scalar.h"

namespace aero::flow {

constexpr int kVars = 5;  // rho, rho u, rho v, rho w, rho E

/// Free-stream conditions. The velocity lies in the X-Z plane: u = Mach (cos alpha, 0, sin alpha)
/// (X streamwise, Z up, Y spanwise / normal to the symmetry plane).
struct FreeStream {
    double mach = 0.5;
    double alphaDeg = 0.0;  // angle of attack, degrees
    double gamma = 1.4;

    double alpha() const { return alphaDeg * 3.14159265358979323846 / 180.0; }
    std::array<double, 3> velocity() const {
        return {mach * std::cos(alpha()), 0.0, mach * std::sin(alpha())};
    }
    double pressure() const { return 1.0 / gamma; }
    double dynamicPressure() const { return 0.5 * mach * mach; }
    /// Conservative free-stream state (rho = 1).
    std::array<double, kVars> state() const {
        const auto u = velocity();
        return {1.0, u[0], u[1], u[2], pressure() / (gamma - 1.0) + 0.5 * mach * mach};
    }
};

// --- Scalar helpers that keep complex-step derivatives intact -------------------------------

/// |x| for real-analytic use: x or -x by the sign of the real part (std::abs of a complex number
/// is its modulus, which would destroy the complex-step derivative).
inline double absR(double x) { return std::abs(x); }
inline std::complex<double> absR(const std::complex<double>& x) { return x.real() < 0 ? -x : x; }

/// max/min by the real part.
template <class T>
inline T maxR(const T& a, const T& b) {
    return realPart(a) >= realPart(b) ? a : b;
}
template <class T>
inline T minR(const T& a, const T& b) {
    return realPart(a) <= realPart(b) ? a : b;
}

// --- Pointwise Euler functions ------------------------------------------------------------

template <class T>
inline T pressure(const T* q, double gamma) {
    return (gamma - 1.0) * (q[4] - 0.5 * (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) / q[0]);
}

template <class T>
inline T soundSpeed(const T* q, double gamma) {
    using std::sqrt;
    return sqrt(gamma * pressure(q, gamma) / q[0]);
}

/// Flux through metric vector n: F_n = (rho U, rho u U + p n, (rho E + p) U) with U = u . n.
template <class T>
inline void normalFlux(const T* q, const T* n, double gamma, T* f) {
    const T rinv = 1.0 / q[0];
    const T U = (q[1] * n[0] + q[2] * n[1] + q[3] * n[2]) * rinv;
    const T p = pressure(q, gamma);
    f[0] = q[0] * U;
    f[1] = q[1] * U + p * n[0];
    f[2] = q[2] * U + p * n[1];
    f[3] = q[3] * U + p * n[2];
    f[4] = (q[4] + p) * U;
}

/// Spectral radius of dF_n/dq: |U| + c |n|.
template <class T>
inline T spectralRadius(const T* q, const T* n, double gamma) {
    using std::sqrt;
    const T U = (q[1] * n[0] + q[2] * n[1] + q[3] * n[2]) / q[0];
    return absR(U) + soundSpeed(q, gamma) * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/// out = |A_n(q)| dq, A_n = dF_n/dq, |A| = X |Lambda| X^-1 in closed form (eigenvalues U, U, U,
/// U + c|n|, U - c|n|):
///   |A| dq = |U| dq + (S1 dp / c^2 + S2 dW / (c |n|)) (1, u, v, w, H)
///                   + (S2 dp / (c |n|) + S1 dW / |n|^2) (0, n_x, n_y, n_z, U)
/// with S1 = (|U + c|n|| + |U - c|n||)/2 - |U|, S2 = (|U + c|n|| - |U - c|n||)/2,
/// dp = (gamma - 1)(|u|^2/2 drho - u . d(rho u) + d(rho E)) and dW = n . d(rho u) - U drho.
template <class T>
inline void absJacobianProduct(const T* q, const T* n, const T* dq, double gamma, T* out) {
    using std::sqrt;
    const T rinv = 1.0 / q[0];
    const T u = q[1] * rinv, v = q[2] * rinv, w = q[3] * rinv;
    const T p = pressure(q, gamma);
    const T c = sqrt(gamma * p * rinv);
    const T H = (q[4] + p) * rinv;
    const T len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    const T len = sqrt(len2);
    const T U = u * n[0] + v * n[1] + w * n[2];
    const T l3 = absR(U), l1 = absR(U + c * len), l2 = absR(U - c * len);
    const T S1 = 0.5 * (l1 + l2) - l3, S2 = 0.5 * (l1 - l2);
    const T dp = (gamma - 1.0) *
                 (0.5 * (u * u + v * v + w * w) * dq[0] - u * dq[1] - v * dq[2] - w * dq[3] + dq[4]);
    const T dW = n[0] * dq[1] + n[1] * dq[2] + n[2] * dq[3] - U * dq[0];
    const T a = S1 * dp / (c * c) + S2 * dW / (c * len);
    const T b = S2 * dp / (c * len) + S1 * dW / len2;
    out[0] = l3 * dq[0] + a;
    out[1] = l3 * dq[1] + a * u + b * n[0];
    out[2] = l3 * dq[2] + a * v + b * n[1];
    out[3] = l3 * dq[3] + a * w + b * n[2];
    out[4] = l3 * dq[4] + a * H + b * U;
}

/// Characteristic upwind flux through n from state qa (this side) to qb (other side):
///   F* = (F_n(qa) + F_n(qb))/2 - |A_n(qm)| (qb - qa)/2,  qm = (qa + qb)/2.
/// Symmetric: F*(qa, qb, n) = -F*(qb, qa, -n), so interface terms telescope.
template <class T>
inline void upwindFlux(const T* qa, const T* qb, const T* n, double gamma, T* f) {
    T fa[kVars], fb[kVars], qm[kVars], dq[kVars], d[kVars];
    normalFlux(qa, n, gamma, fa);
    normalFlux(qb, n, gamma, fb);
    for (int v = 0; v < kVars; ++v) {
        qm[v] = 0.5 * (qa[v] + qb[v]);
        dq[v] = qb[v] - qa[v];
    }
    absJacobianProduct(qm, n, dq, gamma, d);
    for (int v = 0; v < kVars; ++v) f[v] = 0.5 * (fa[v] + fb[v]) - 0.5 * d[v];
}

}  // namespace aero::flow
