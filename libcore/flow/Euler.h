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

#include "common/Dual.h"
#include "common/Scalar.h"

namespace aero::flow {

constexpr int kVars = 5;  // rho, rho u, rho v, rho w, rho E

/// The grid sensitivities' scalar: a dual number with one direction per metric value of a node
/// (kMetricWidth, Metrics.h); the residual and the boundary fluxes are instantiated for it.
using MetricDual = Dual<10>;
/// The exact Jacobian's scalar: one direction per state variable of a node.
using StateDual = Dual<kVars>;

/// X(T) for every scalar type the residual, the dissipation and the boundary fluxes are
/// instantiated for (each .cpp defines X as its explicit instantiations of T).
#define AERO_FLOW_SCALARS(X) X(double) X(std::complex<double>) X(MetricDual) X(StateDual)

/// The interior inviscid discretization. Central: D_d(m_d . F) with nodal fluxes (the classical
/// conservative form). EntropyConservative: the same SBP operator in flux-difference form with the
/// two-point flux F_ec(q_i, q_i+1, (m_i + m_i+1)/2) between neighbours (below), and the
/// interface and farfield SATs built on F_ec: the discretization then conserves entropy except
/// for the dissipation and the boundary terms, which only produce it.
enum class InviscidScheme { Central, EntropyConservative };


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

/// Logarithmic mean (a - b) / (ln a - ln b) of two positive numbers, written as
/// (a + b) / (2 atanh(f) / f) with f = (a - b) / (a + b), and a series in f^2 when |f| < 1e-2
/// (its truncation error f^8 / 9 is below round-off), so it is smooth and complex-step
/// differentiable through a = b.
template <class T>
inline T logMean(const T& a, const T& b) {
    using std::atanh;
    const T f = (a - b) / (a + b);
    const T u = f * f;
    const T F = realPart(u) < 1e-4 ? 1.0 + u * (1.0 / 3.0 + u * (1.0 / 5.0 + u * (1.0 / 7.0))) : atanh(f) / f;
    return 0.5 * (a + b) / F;
}

/// Entropy variables w = dU/dq of the entropy function U = -rho s / (gamma - 1),
/// s = ln p - gamma ln rho: w = ((gamma - s)/(gamma - 1) - rho |u|^2 / (2p), rho u / p, -rho / p).
template <class T>
inline void entropyVariables(const T* q, double gamma, T* w) {
    using std::log;
    const T p = pressure(q, gamma);
    const T s = log(p) - gamma * log(q[0]);
    const T k = 0.5 * (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) / q[0];
    w[0] = (gamma - s) / (gamma - 1.0) - k / p;
    w[1] = q[1] / p;
    w[2] = q[2] / p;
    w[3] = q[3] / p;
    w[4] = -q[0] / p;
}

/// Entropy-conservative two-point flux through n (Chandrashekar, Commun. Comput. Phys. 14, 2013):
/// with logarithmic means rho^ and beta^ of rho and beta = rho / (2p), arithmetic means (bar),
///   F_rho = rho^ (u_bar . n),  F_m = p~ n + u_bar F_rho  (p~ = rho_bar / (2 beta_bar)),
///   F_E = (1 / (2 (gamma - 1) beta^) - |u|^2_bar / 2) F_rho + u_bar . F_m.
/// Consistent (F(q, q) = F_n(q)), symmetric, and (w_b - w_a) . F = rho_b U_b - rho_a U_a
/// (Tadmor's condition, U = u . n): a flux difference of these conserves entropy exactly.
template <class T>
inline void entropyConservativeFlux(const T* qa, const T* qb, const T* n, double gamma, T* f) {
    const T ra = 1.0 / qa[0], rb = 1.0 / qb[0];
    const T ua[3] = {qa[1] * ra, qa[2] * ra, qa[3] * ra}, ub[3] = {qb[1] * rb, qb[2] * rb, qb[3] * rb};
    const T ka = ua[0] * ua[0] + ua[1] * ua[1] + ua[2] * ua[2];
    const T kb = ub[0] * ub[0] + ub[1] * ub[1] + ub[2] * ub[2];
    const T pa = (gamma - 1.0) * (qa[4] - 0.5 * qa[0] * ka), pb = (gamma - 1.0) * (qb[4] - 0.5 * qb[0] * kb);
    const T ba = 0.5 * qa[0] / pa, bb = 0.5 * qb[0] / pb;
    const T rhoLn = logMean(qa[0], qb[0]), betaLn = logMean(ba, bb);
    const T u[3] = {0.5 * (ua[0] + ub[0]), 0.5 * (ua[1] + ub[1]), 0.5 * (ua[2] + ub[2])};
    const T pt = 0.5 * (qa[0] + qb[0]) / (ba + bb);
    const T un = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
    f[0] = rhoLn * un;
    f[1] = pt * n[0] + u[0] * f[0];
    f[2] = pt * n[1] + u[1] * f[0];
    f[3] = pt * n[2] + u[2] * f[0];
    f[4] = (1.0 / (2.0 * (gamma - 1.0) * betaLn) - 0.25 * (ka + kb)) * f[0] + u[0] * f[1] + u[1] * f[2] + u[2] * f[3];
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

/// The same upwinding with the entropy-conservative flux as its central part:
///   F* = F_ec(qa, qb, n) - |A_n(qm)| (qb - qa)/2.
template <class T>
inline void entropyUpwindFlux(const T* qa, const T* qb, const T* n, double gamma, T* f) {
    T qm[kVars], dq[kVars], d[kVars];
    entropyConservativeFlux(qa, qb, n, gamma, f);
    for (int v = 0; v < kVars; ++v) {
        qm[v] = 0.5 * (qa[v] + qb[v]);
        dq[v] = qb[v] - qa[v];
    }
    absJacobianProduct(qm, n, dq, gamma, d);
    for (int v = 0; v < kVars; ++v) f[v] -= 0.5 * d[v];
}

}  // namespace aero::flow
