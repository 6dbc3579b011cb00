#pragma once
// Scalar artificial dissipation (Jameson-Schmidt-Turkel coefficients with a pressure switch) in
// the SBP-compatible form of Mattsson, Svard & Nordstrom (J Sci Comput 21, 2004): along each
// direction d of a block, with undivided difference operators Dt1 ((n-1) x n, (Dt1 q)_{i+1/2} =
// q_{i+1} - q_i) and Dt2 ((n-2) x n, (Dt2 q)_m = q_{m-1} - 2 q_m + q_{m+1}, m = 1..n-2),
//   R += H^-1 Dt1^T E2 Dt1 q + H^-1 Dt2^T E4 Dt2 q,
//   E2 at i+1/2: eps2 = kappa2 (lambda_i + lambda_{i+1})/2 max(nu_i, nu_{i+1}),
//   E4 at node m: eps4 = lambda_m max(0, kappa4 - kappa2 nu_m),
//   nu_i = |p_{i+1} - 2 p_i + p_{i-1}| / (p_{i+1} + 2 p_i + p_{i-1})  (nu_0 = nu_1, nu_{n-1} = nu_{n-2}),
//   lambda_i = |m_d . u| + c |m_d|  (spectral radius of the direction's flux Jacobian).
// Both terms are symmetric positive semidefinite in the H norm (dissipative up to the block
// boundaries) and annihilate constants (conservative: their H-weighted sum is zero). A node's
// term reaches 2 nodes along each grid line: the residual keeps a 13-point stencil.
//
// The preconditioner's variant ("lumped"): the fourth difference is dropped and its coefficient
// added to the second, eps2' = eps2 + sigma (eps4_i + eps4_{i+1})/2 (Pueyo & Zingg), giving a
// 7-point stencil.
#include <array>
#include <vector>

#include "flow/BlockView.h"
#include "flow/Euler.h"

namespace aero::flow {

struct DissipationOptions {
    double kappa2 = 0.5;   // second difference (shocks), scaled by the pressure switch
    double kappa4 = 0.02;  // fourth difference (background). With the central scheme 0.02 let an
                           // unstable mode grow at the half-sphere's rear stagnation point (0.05
                           // was needed); the entropy-conservative scheme is stable at 0.01
                           // (docs/validation.md)
    bool gridAware = true;   // the fourth difference's second differences weighted by the node
                             // spacing along the line (h = (1/J) / |m_d|), so they vanish on
                             // fields linear in arc length: on a stretched grid the index-space
                             // difference (q0 - 2 q1 + q2) of a smooth field is (r - 1) h dq/dn,
                             // a first-order dissipation (an O(1) numerical friction at walls)
    double lumping = 3.0;   // sigma of the lumped (preconditioner) variant. The approximate-Newton
                            // start-up converges at the rate the lumped operator matches the
                            // real one: on the 11,340-node half-sphere sigma 16 takes 152
                            // iterations, 8: 89, 4: 55, 3: 47 (with ILU(1)), 2: 38
                            // (docs/validation.md); ILU(1-2) of it stays stable from 2 on
                            // (ILU(0) breaks down below about 16)
    double switchSmoothing = 0;  // delta > 0: the switch's max() replaced by smooth versions of
                                 // width delta (max(nu_a, nu_b) = (a + b + sqrt((a - b)^2 +
                                 // delta^2) - delta) / 2, and max(0, kappa4 - kappa2 nu) with
                                 // width delta kappa4), so Newton does not chatter where the
                                 // switch changes branch at a shock (docs/validation.md); 0: the
                                 // kinked form. The switch's |.| stays exact: its kink sits where
                                 // the switch is zero, so the coefficients it changes are tiny
                                 // there. Its smooth form sqrt(nu^2 + delta^2) - delta (used up to
                                 // the twenty-sixth session) cut the second difference wherever
                                 // nu < delta: 37 % more lift on an optimizer's design at 14,580
                                 // nodes, against 5 % for the smooth maxima alone
};

/// max(a, b) of the switch: by the real part, or smooth with width delta (a lower bound of max
/// within delta / 2, equal to it for a = b).
template <class T>
inline T switchMax(const T& a, const T& b, double delta) {
    using std::sqrt;
    if (delta <= 0) return maxR(a, b);
    const T d = a - b;
    return 0.5 * (a + b + sqrt(d * d + delta * delta) - delta);
}

/// Pressure-switch and spectral-radius fields of one block, per direction: lambda[d][node],
/// nu[d][node].
template <class T>
struct DissipationFields {
    std::array<std::vector<T>, 3> lambda, nu;
    std::array<std::vector<T>, 3> spacing;  // (1/J) / |m_d| per node (only with gridAware)
};

/// Fills `f` for block data q (width 5) and metrics (width kMetricWidth). `freeze`: compute the
/// fields from the real part of q only (the coefficients are then constants for complex-step
/// derivatives: the frozen-coefficient Jacobian).
template <class T>
void dissipationFields(const BlockView<const T>& q, const BlockView<const T>& metrics, double gamma,
                       bool freeze, DissipationFields<T>& f, bool spacing = false);

template <class T>
inline T eps2Half(const T& lamA, const T& lamB, const T& nuA, const T& nuB,
                  const DissipationOptions& o) {
    return o.kappa2 * 0.5 * (lamA + lamB) * switchMax(nuA, nuB, o.switchSmoothing);
}
template <class T>
inline T eps4Node(const T& lam, const T& nu, const DissipationOptions& o) {
    return lam * switchMax(T(0.0), T(o.kappa4 - o.kappa2 * nu), o.switchSmoothing * o.kappa4);
}
/// The lumped variant's coefficient at i+1/2.
template <class T>
inline T eps2Lumped(const T& lamA, const T& lamB, const T& nuA, const T& nuB,
                    const DissipationOptions& o) {
    return eps2Half(lamA, lamB, nuA, nuB, o) +
           o.lumping * 0.5 * (eps4Node(lamA, nuA, o) + eps4Node(lamB, nuB, o));
}

/// Adds the dissipation of one block to r (width 5). `lumped` selects the preconditioner variant.
template <class T>
void addDissipation(const BlockView<const T>& q, const BlockView<const T>& metrics,
                    const DissipationOptions& o, double gamma, bool lumped, bool freeze,
                    const BlockView<T>& r);

}  // namespace aero::flow
