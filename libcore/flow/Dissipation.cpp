#include "flow/Dissipation.h"

#include <complex>

#include "flow/Metrics.h"
#include "flow/Sbp.h"

namespace aero::flow {

namespace {
template <class T>
T frozen(const T& x, bool freeze) {
    return freeze ? T(realPart(x)) : x;
}
}  // namespace

template <class T>
void dissipationFields(const BlockView<const T>& q, const BlockView<const T>& metrics, double gamma,
                       bool freeze, DissipationFields<T>& f, bool spacing) {
    using std::sqrt;
    const long N = q.nodeCount();
    std::vector<T> p(N);
    for (int d = 0; d < 3; ++d) {
        f.lambda[d].resize(N);
        f.nu[d].resize(N);
        f.spacing[d].resize(spacing ? N : 0);
    }
#pragma omp parallel for schedule(static)
    for (long n = 0; n < N; ++n) {
        const T* qn = q.at(n);
        p[n] = frozen(pressure(qn, gamma), freeze);
        for (int d = 0; d < 3; ++d) {
            f.lambda[d][n] = frozen(spectralRadius(qn, metrics.at(n) + 3 * d, gamma), freeze);
            if (spacing) {
                const T* m = metrics.at(n) + 3 * d;
                f.spacing[d][n] = metrics.at(n)[9] / sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
            }
        }
    }
    const std::array<int, 3> dims = q.dims;
#pragma omp parallel for schedule(static)
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const int idx[3] = {i, j, k};
                const long n = q.node(i, j, k);
                for (int d = 0; d < 3; ++d) {
                    const int len = dims[d];
                    const long s = q.stride(d);
                    if (len < 3) {
                        f.nu[d][n] = 0.0;
                        continue;
                    }
                    // The switch at a boundary node is its neighbour's.
                    const long c = idx[d] == 0 ? n + s : (idx[d] == len - 1 ? n - s : n);
                    const T num = p[c + s] - 2.0 * p[c] + p[c - s];
                    const T den = p[c + s] + 2.0 * p[c] + p[c - s];
                    // Exact |.| also with DissipationOptions::switchSmoothing: its kink is
                    // where the switch vanishes, and smoothing it takes the second difference
                    // away wherever the switch is below the width (Dissipation.h).
                    f.nu[d][n] = absR(num) / den;
                }
            }
        }
    }
}

template <class T>
void addDissipation(const BlockView<const T>& q, const BlockView<const T>& metrics,
                    const DissipationOptions& o, double gamma, bool lumped, bool freeze,
                    const BlockView<T>& r) {
    DissipationFields<T> f;
    dissipationFields(q, metrics, gamma, freeze, f, o.gridAware && !lumped);
    const std::array<int, 3> dims = q.dims;
    const long N = q.nodeCount();
    // The rows m = 1..len-2 of the second-difference operator, once per node and direction: the
    // weights (wm, -2, wp) on nodes m-1, m, m+1 ((1, -2, 1), or weighted by the spacing so that
    // the row vanishes on linear fields), the fourth-difference coefficient at m, and the row
    // applied to q. The fourth difference at a node sums three rows; computing each where it is
    // used did every row three times. The same expressions, so the same bits.
    std::array<std::vector<T>, 3> rowM, rowP, eps4, d2q;
    if (!lumped) {
        for (int d = 0; d < 3; ++d) {
            const int len = dims[d];
            if (len < 3) continue;
            const long s = q.stride(d);
            rowM[d].resize(N);
            rowP[d].resize(N);
            eps4[d].resize(N);
            d2q[d].resize(kVars * static_cast<std::size_t>(N));
#pragma omp parallel for schedule(static)
            for (int k = 0; k < dims[2]; ++k) {
                for (int j = 0; j < dims[1]; ++j) {
                    for (int i = 0; i < dims[0]; ++i) {
                        const int idx[3] = {i, j, k};
                        if (idx[d] < 1 || idx[d] > len - 2) continue;
                        const long m = q.node(i, j, k);
                        T wm(1.0), wp(1.0);
                        if (o.gridAware) {
                            const std::vector<T>& h = f.spacing[d];
                            const T hm = h[m - s] + h[m], hp = h[m] + h[m + s];
                            wm = 2.0 * hp / (hm + hp);
                            wp = 2.0 * hm / (hm + hp);
                        }
                        rowM[d][m] = wm;
                        rowP[d][m] = wp;
                        eps4[d][m] = eps4Node(f.lambda[d][m], f.nu[d][m], o);
                        const T* qm = q.at(m - s);
                        const T* q0 = q.at(m);
                        const T* qp = q.at(m + s);
                        T* out = &d2q[d][kVars * m];
                        for (int v = 0; v < kVars; ++v) out[v] = wm * qm[v] - 2.0 * q0[v] + wp * qp[v];
                    }
                }
            }
        }
    }
#pragma omp parallel for schedule(static)
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const int idx[3] = {i, j, k};
                const long n = q.node(i, j, k);
                T* rn = r.at(n);
                for (int d = 0; d < 3; ++d) {
                    const int len = dims[d];
                    const int a = idx[d];
                    const long s = q.stride(d);
                    const std::vector<T>& lam = f.lambda[d];
                    const std::vector<T>& nu = f.nu[d];
                    T acc[kVars] = {};
                    // Second difference: (f_{i-1/2} - f_{i+1/2}), f_{m+1/2} = eps (q_{m+1} - q_m).
                    if (a > 0) {
                        const T e = lumped ? eps2Lumped(lam[n - s], lam[n], nu[n - s], nu[n], o)
                                           : eps2Half(lam[n - s], lam[n], nu[n - s], nu[n], o);
                        const T* q0 = q.at(n - s);
                        const T* q1 = q.at(n);
                        for (int v = 0; v < kVars; ++v) acc[v] += e * (q1[v] - q0[v]);
                    }
                    if (a < len - 1) {
                        const T e = lumped ? eps2Lumped(lam[n], lam[n + s], nu[n], nu[n + s], o)
                                           : eps2Half(lam[n], lam[n + s], nu[n], nu[n + s], o);
                        const T* q0 = q.at(n);
                        const T* q1 = q.at(n + s);
                        for (int v = 0; v < kVars; ++v) acc[v] -= e * (q1[v] - q0[v]);
                    }
                    // Fourth difference: (Dt2^T E4 Dt2 q)_i over the rows m = i-1, i, i+1 in
                    // 1..len-2.
                    if (!lumped) {
                        for (int m = a - 1; m <= a + 1; ++m) {
                            if (m < 1 || m > len - 2) continue;
                            const long nm = n + (m - a) * s;
                            // q_n's weight in row m
                            const T coef = m == a ? T(-2.0) : (m < a ? rowP[d][nm] : rowM[d][nm]);
                            const T w = coef * eps4[d][nm];
                            const T* row = &d2q[d][kVars * nm];
                            for (int v = 0; v < kVars; ++v) acc[v] += w * row[v];
                        }
                    }
                    const double hinv = 1.0 / sbpWeight(a, len);
                    for (int v = 0; v < kVars; ++v) rn[v] += hinv * acc[v];
                }
            }
        }
    }
}

#define AERO_INSTANTIATE(T)                                                                        \
    template void dissipationFields<T>(const BlockView<const T>&, const BlockView<const T>&,      \
                                       double, bool, DissipationFields<T>&, bool);                       \
    template void addDissipation<T>(const BlockView<const T>&, const BlockView<const T>&,         \
                                    const DissipationOptions&, double, bool, bool,                 \
                                    const BlockView<T>&);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
