#include "nurbs/Volume.h"

#include <gtest/gtest.h>

#include <complex>

#include "RandomNurbs.h"

using namespace aero;
using namespace aero::nurbs;
using cplx = std::complex<double>;

TEST(Volume, JacobianAgreesWithComplexStep) {
    std::mt19937 rng(31);
    const double h = 1e-30;
    for (int trial = 0; trial < 40; ++trial) {
        const std::array<int, 3> p = {1 + trial % 3, 1 + (trial / 3) % 3, 1 + trial % 2};
        const Volume<double> v = test::randomVolume(rng, p, {p[0] + 2, p[1] + 3, p[2] + 1}, trial % 2 == 0);
        const Volume<cplx> vc = test::cast<cplx>(v);
        std::uniform_real_distribution<double> D(0.0, 1.0);
        const double x[3] = {D(rng), D(rng), D(rng)};
        Vec3<double> P;
        Eigen::Matrix3d J;
        evaluateJacobian(v, x[0], x[1], x[2], P, J);
        for (int c = 0; c < 3; ++c) {
            cplx xc[3] = {x[0], x[1], x[2]};
            xc[c] += cplx(0.0, h);
            const Vec3<cplx> Pc = evaluate(vc, xc[0], xc[1], xc[2]);
            for (int r = 0; r < 3; ++r) {
                EXPECT_NEAR(J(r, c), Pc[r].imag() / h, 1e-13 * std::max(1.0, J.norm()));
                EXPECT_NEAR(P[r], Pc[r].real(), 1e-14);
            }
        }
    }
}

TEST(Volume, BasisAtIsThePartitionOfUnityAndTheControlPointSensitivity) {
    // Eq. 3 of the paper: dV/dB_a = R_a(xi) I. Checked by complex step on each coordinate.
    std::mt19937 rng(12);
    for (bool rational : {false, true}) {
        const Volume<double> v = test::randomVolume(rng, {3, 2, 1}, {6, 5, 3}, rational);
        const double xi[3] = {0.37, 0.81, 0.12};
        int idx[64];
        double val[64];
        const int n = basisAt(v, xi, idx, val);
        EXPECT_EQ(n, 4 * 3 * 2);
        double sum = 0;
        Vec3<double> P = Vec3<double>::Zero();
        for (int m = 0; m < n; ++m) {
            sum += val[m];
            P += val[m] * Vec3<double>(v.points[3 * idx[m]], v.points[3 * idx[m] + 1], v.points[3 * idx[m] + 2]);
        }
        EXPECT_NEAR(sum, 1.0, 1e-14);
        EXPECT_NEAR((P - evaluate(v, xi[0], xi[1], xi[2])).norm(), 0.0, 1e-14);
        for (int m = 0; m < n; m += 5) {
            Volume<cplx> vc = test::cast<cplx>(v);
            vc.points[3 * idx[m] + 2] += cplx(0.0, 1e-30);
            const Vec3<cplx> Pc = evaluate(vc, cplx(xi[0]), cplx(xi[1]), cplx(xi[2]));
            EXPECT_NEAR(Pc[2].imag() / 1e-30, val[m], 1e-15);
            EXPECT_EQ(Pc[0].imag(), 0.0);
        }
    }
}

TEST(Volume, SumFactorizedSamplingEqualsPointEvaluation) {
    std::mt19937 rng(13);
    for (bool rational : {false, true}) {
        const Volume<double> v = test::randomVolume(rng, {3, 3, 2}, {7, 6, 5}, rational);
        std::vector<double> s0(19), s1(13), s2(11);
        for (auto* s : {&s0, &s1, &s2}) {
            for (std::size_t a = 0; a < s->size(); ++a) (*s)[a] = static_cast<double>(a) / (s->size() - 1);
        }
        std::vector<double> out(3 * s0.size() * s1.size() * s2.size());
        sampleGrid(v, s0, s1, s2, out.data());
        std::size_t o = 0;
        for (double z : s2) {
            for (double y : s1) {
                for (double x : s0) {
                    const Vec3<double> P = evaluate(v, x, y, z);
                    for (int k = 0; k < 3; ++k, ++o) ASSERT_NEAR(out[o], P[k], 1e-14);
                }
            }
        }
    }
}

TEST(Volume, TrilinearBoxIsTheIdentityMap) {
    Volume<double> v;
    v.degree = {1, 1, 1};
    v.count = {2, 2, 2};
    for (auto& k : v.knots) k = {0, 0, 1, 1};
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 2; ++j) {
            for (int i = 0; i < 2; ++i) v.points.insert(v.points.end(), {double(i), double(j), double(k)});
        }
    }
    const Vec3<double> P = evaluate(v, 0.25, 0.5, 0.75);
    EXPECT_DOUBLE_EQ(P[0], 0.25);
    EXPECT_DOUBLE_EQ(P[1], 0.5);
    EXPECT_DOUBLE_EQ(P[2], 0.75);
}
