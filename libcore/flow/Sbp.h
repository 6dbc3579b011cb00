#pragma once
// The second-order diagonal-norm summation-by-parts operator on a line of n >= 2 nodes with unit
// computational spacing: D = H^-1 Q,
//   (D u)_0 = u_1 - u_0,   (D u)_i = (u_{i+1} - u_{i-1}) / 2,   (D u)_{n-1} = u_{n-1} - u_{n-2},
//   H = diag(1/2, 1, ..., 1, 1/2),   Q + Q^T = diag(-1, 0, ..., 0, 1).
// In 3D the operators act along i, j, k separately (tensor products), so they commute; that is
// what makes the metric identities (and free-stream preservation) exact.

namespace aero::flow {

/// H_ii of a line of n nodes.
inline double sbpWeight(int i, int n) { return (i == 0 || i == n - 1) ? 0.5 : 1.0; }

/// (D u)_i where `u` points at node i's value and neighbours are `stride` elements apart.
template <class T>
inline T sbpDiff(const T* u, long stride, int i, int n) {
    if (i == 0) return u[stride] - u[0];
    if (i == n - 1) return u[0] - u[-stride];
    return 0.5 * (u[stride] - u[-stride]);
}

}  // namespace aero::flow
