// The scalar dissipation (flow/Dissipation.h) on one Cartesian block: the pressure switch is zero
// for a pressure linear along the line and 1/5 beside a jump of one to two, where it turns the
// fourth difference off and the second on; a constant state is untouched; with the grid-aware
// form a field linear in arc length on a stretched line is untouched too (the index-space form
// damps it: a first-order numerical friction); the smooth maximum is a lower bound within
// delta / 2.
#include "flow/Dissipation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "flow/Euler.h"
#include "flow/Metrics.h"

using namespace aero::flow;

namespace {

// A block of n x 3 x 3 nodes with node spacing h_i along i (1 along j and k): the metrics of the
// Cartesian grid, m_xi = (1/h_i, 0, 0) / J with 1/J = h_i.
struct LineBlock {
    std::array<int, 3> dims;
    std::vector<double> metrics, q;

    LineBlock(const std::vector<double>& h, const std::vector<double>& pressure, const std::vector<double>& u)
        : dims{static_cast<int>(h.size()), 3, 3} {
        const long N = static_cast<long>(dims[0]) * dims[1] * dims[2];
        metrics.assign(kMetricWidth * N, 0.0);
        q.assign(kVars * N, 0.0);
        for (long n = 0; n < N; ++n) {
            const int i = static_cast<int>(n % dims[0]);
            double* m = &metrics[kMetricWidth * n];
            m[0] = 1.0;   // (1/h) * (1/J) = 1
            m[4] = h[i];  // m_eta = (0, 1, 0) / J
            m[8] = h[i];  // m_zeta = (0, 0, 1) / J
            m[9] = h[i];
            double* a = &q[kVars * n];
            a[0] = 1.0;
            a[1] = u[i];
            a[4] = pressure[i] / 0.4 + 0.5 * u[i] * u[i];
        }
    }
    BlockView<const double> qView() const { return {q.data(), dims, kVars}; }
    BlockView<const double> mView() const { return {metrics.data(), dims, kMetricWidth}; }
    std::vector<double> dissipation(const DissipationOptions& o) const {
        std::vector<double> r(q.size(), 0.0);
        addDissipation(qView(), mView(), o, 1.4, false, false, BlockView<double>{r.data(), dims, kVars});
        return r;
    }
    long node(int i) const { return i + static_cast<long>(dims[0]) * (1 + 3 * 1); }  // j = k = 1
};

double maxAbs(const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
}

TEST(Dissipation, SwitchIsZeroForALinearPressureAndTurnsTheFourthDifferenceOffAtAJump) {
    const int n = 12;
    std::vector<double> h(n, 1.0), linear(n), jump(n), u(n, 0.5);
    for (int i = 0; i < n; ++i) {
        linear[i] = 1.0 + 0.05 * i;
        jump[i] = i < n / 2 ? 1.0 : 2.0;
    }
    DissipationOptions o;
    {
        const LineBlock b(h, linear, u);
        DissipationFields<double> f;
        dissipationFields(b.qView(), b.mView(), 1.4, false, f);
        for (int i = 0; i < n; ++i) EXPECT_NEAR(f.nu[0][b.node(i)], 0.0, 1e-15) << i;
    }
    const LineBlock b(h, jump, u);
    DissipationFields<double> f;
    dissipationFields(b.qView(), b.mView(), 1.4, false, f);
    // Beside the jump (nodes n/2 - 1 and n/2): |1 - 2 + 2| / (1 + 2 + 2) and |1 - 4 + 2| / (1 + 4 + 2).
    EXPECT_NEAR(f.nu[0][b.node(n / 2 - 1)], 1.0 / 5.0, 1e-15);
    EXPECT_NEAR(f.nu[0][b.node(n / 2)], 1.0 / 7.0, 1e-15);
    EXPECT_EQ(f.nu[0][b.node(2)], 0.0);
    // kappa2 nu > kappa4 there: no fourth difference, a second difference of kappa2 lambda nu.
    const double lam = f.lambda[0][b.node(n / 2)];
    EXPECT_NEAR(lam, 0.5 + std::sqrt(1.4 * 2.0 / 1.0), 1e-12);  // |u| + c with the metrics 1
    EXPECT_EQ(eps4Node(lam, f.nu[0][b.node(n / 2)], o), 0.0);
    EXPECT_NEAR(eps2Half(lam, lam, f.nu[0][b.node(n / 2 - 1)], f.nu[0][b.node(n / 2)], o), o.kappa2 * lam / 5.0, 1e-14);
    // Away from it the background coefficient.
    const double lam2 = f.lambda[0][b.node(2)];
    EXPECT_NEAR(eps4Node(lam2, f.nu[0][b.node(2)], o), o.kappa4 * lam2, 1e-15);
    EXPECT_EQ(eps2Half(lam2, lam2, 0.0, 0.0, o), 0.0);
    // The lumped (preconditioner) coefficient moves the fourth difference to the second.
    EXPECT_NEAR(eps2Lumped(lam2, lam2, 0.0, 0.0, o), o.lumping * o.kappa4 * lam2, 1e-15);
}

TEST(Dissipation, LeavesAConstantStateAndAFieldLinearInArcLengthUntouched) {
    // A line stretched by 1.3 per cell (a wall layer), velocity linear in arc length.
    const int n = 14;
    std::vector<double> h(n), s(n), p(n, 1.0 / 1.4), u(n), uniform(n, 0.5);
    for (int i = 0; i < n; ++i) h[i] = 0.01 * std::pow(1.3, i);
    // The node spacing the dissipation sees is the metric's (1/J)/|m_xi| = h_i: the nodes'
    // arc-length positions consistent with it (s_{i+1} - s_i = (h_i + h_{i+1}) / 2).
    s[0] = 0;
    for (int i = 1; i < n; ++i) s[i] = s[i - 1] + 0.5 * (h[i - 1] + h[i]);
    for (int i = 0; i < n; ++i) u[i] = 0.3 + 2.0 * s[i];
    DissipationOptions o;
    o.kappa2 = 0;  // the fourth difference alone (the switch is zero here anyway: constant p)
    EXPECT_LT(maxAbs(LineBlock(h, p, uniform).dissipation(o)), 1e-15);

    o.gridAware = true;
    const std::vector<double> aware = LineBlock(h, p, u).dissipation(o);
    o.gridAware = false;
    const std::vector<double> index = LineBlock(h, p, u).dissipation(o);
    // The x-momentum (rho u, rho = 1) is linear in arc length (the energy, with u^2 / 2, is not).
    // The index-space second difference of a linear field on a stretched line is (r - 1) h du/ds:
    // not zero, so it damps the velocity gradient; the grid-aware one leaves it alone.
    double awareMomentum = 0, indexMomentum = 0;
    for (std::size_t a = 1; a < aware.size(); a += kVars) {
        awareMomentum = std::max(awareMomentum, std::abs(aware[a]));
        indexMomentum = std::max(indexMomentum, std::abs(index[a]));
    }
    EXPECT_GT(indexMomentum, 1e-4);
    EXPECT_LT(awareMomentum, 1e-12 * indexMomentum / 1e-4) << awareMomentum << " vs " << indexMomentum;
}

TEST(Dissipation, SmoothMaximumIsALowerBoundWithinHalfItsWidth) {
    for (double delta : {1e-3, 1e-2, 0.1}) {
        for (double a : {-0.3, 0.0, 0.01, 0.2}) {
            for (double b : {-0.2, 0.0, 0.005, 0.2}) {
                const double m = switchMax(a, b, delta);
                EXPECT_LE(m, std::max(a, b) + 1e-15);
                EXPECT_GE(m, std::max(a, b) - 0.5 * delta - 1e-15);
            }
            EXPECT_NEAR(switchMax(a, a, delta), a, 1e-15);
        }
    }
    EXPECT_EQ(switchMax(0.1, 0.3, 0.0), 0.3);  // width 0: the kinked maximum
}

}  // namespace
