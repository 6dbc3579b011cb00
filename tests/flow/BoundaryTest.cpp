// The boundary fluxes (flow/bc/BoundaryFlux.h) against the Euler flux written out by hand in
// primitive variables: a slip wall passes only its Riemann pressure p* = p + rho u_n (u_n + c)
// along the normal (mass and energy rows penalize the normal velocity; the boundary's entropy
// flux is rho^2 u_n^2 (u_n + c) |n| / p, non-negative exactly for u_n > -c) and agrees with the
// upwind flux against the mirror state to third order in u_n; the symmetry plane holds a free
// stream in the X-Z plane; the farfield returns the free stream's flux for the free stream, and
// its linearization about it is A^+ (the interior supplies the outgoing characteristics, the free
// stream the others: 4, 1, 5 and 0 taken from outside for subsonic inflow, subsonic outflow,
// supersonic inflow and outflow); the interface flux is consistent, conservative (the two sides'
// SATs cancel), upwinds to A^+ / A^- and, in its entropy form, only produces entropy; wall and
// interface commute with rotations.
#include "flow/bc/BoundaryFlux.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "common/Error.h"

using namespace aero;
using namespace aero::flow;
using cplx = std::complex<double>;

namespace {

const double kGamma = 1.4;

struct Primitive {
    double rho, u, v, w, p;
};

std::array<double, 5> conservative(const Primitive& s) {
    return {s.rho, s.rho * s.u, s.rho * s.v, s.rho * s.w,
            s.p / (kGamma - 1.0) + 0.5 * s.rho * (s.u * s.u + s.v * s.v + s.w * s.w)};
}

// The Euler flux through the metric vector n, written out: (rho U, rho u U + p n, (rho E + p) U).
template <class T>
void handFlux(const T* q, const double* n, T* f) {
    const T rho = q[0], u = q[1] / rho, v = q[2] / rho, w = q[3] / rho;
    const T p = (kGamma - 1.0) * (q[4] - 0.5 * rho * (u * u + v * v + w * w));
    const T U = u * n[0] + v * n[1] + w * n[2];
    f[0] = rho * U;
    f[1] = rho * u * U + p * n[0];
    f[2] = rho * v * U + p * n[1];
    f[3] = rho * w * U + p * n[2];
    f[4] = (q[4] + p) * U;
}

std::array<double, 5> handFlux(const std::array<double, 5>& q, const double* n) {
    std::array<double, 5> f;
    handFlux(q.data(), n, f.data());
    return f;
}

double norm3(const double* a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

// A random state with Mach number below `maxMach` and a random metric vector of length 0.2 .. 3.
void randomState(std::mt19937& rng, double maxMach, Primitive& s, double* n) {
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    s.rho = 1.0 + 0.5 * U(rng);
    s.p = (1.0 + 0.5 * U(rng)) / kGamma;
    const double c = std::sqrt(kGamma * s.p / s.rho);
    double u[3] = {U(rng), U(rng), U(rng)};
    const double scale = maxMach * c * std::abs(U(rng)) / norm3(u);
    s.u = scale * u[0];
    s.v = scale * u[1];
    s.w = scale * u[2];
    for (int a = 0; a < 3; ++a) n[a] = U(rng);
    const double len = 0.2 + 2.8 * std::abs(U(rng));
    const double l = norm3(n);
    for (int a = 0; a < 3; ++a) n[a] *= len / l;
}

using Matrix5 = Eigen::Matrix<double, 5, 5>;

// d flux / d q at q by complex step, flux(qc, out) evaluated in complex arithmetic.
template <class F>
Matrix5 complexStepJacobian(const std::array<double, 5>& q, F flux) {
    Matrix5 J;
    const double h = 1e-30;
    for (int c = 0; c < 5; ++c) {
        cplx qc[5], f[5];
        for (int v = 0; v < 5; ++v) qc[v] = q[v];
        qc[c] += cplx(0, h);
        flux(qc, f);
        for (int v = 0; v < 5; ++v) J(v, c) = f[v].imag() / h;
    }
    return J;
}

// Eigenvalues of a matrix known to have real ones, ascending.
std::array<double, 5> sortedEigenvalues(const Matrix5& M) {
    Eigen::EigenSolver<Matrix5> es(M, false);
    std::array<double, 5> lam;
    for (int i = 0; i < 5; ++i) {
        EXPECT_NEAR(es.eigenvalues()[i].imag(), 0.0, 1e-7);
        lam[i] = es.eigenvalues()[i].real();
    }
    std::sort(lam.begin(), lam.end());
    return lam;
}

// Rotation by Euler angles (a, b, c): Rz(a) Ry(b) Rx(c).
Eigen::Matrix3d rotation(double a, double b, double c) {
    return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();
}

// The state and a 5-vector flux with their momentum parts rotated by R.
std::array<double, 5> rotated(const Eigen::Matrix3d& R, const std::array<double, 5>& q) {
    const Eigen::Vector3d m = R * Eigen::Vector3d(q[1], q[2], q[3]);
    return {q[0], m[0], m[1], m[2], q[4]};
}

}  // namespace

// --- Slip wall -----------------------------------------------------------------------------

TEST(SlipWall, PassesOnlyTheRiemannPressureAlongTheNormal) {
    std::mt19937 rng(3);
    const FreeStream fs;
    for (int trial = 0; trial < 50; ++trial) {
        Primitive s;
        double n[3];
        randomState(rng, 1.5, s, n);
        const double len = norm3(n), nhat[3] = {n[0] / len, n[1] / len, n[2] / len};
        const auto q = conservative(s);
        double f[5];
        slipWallFlux<double>(q.data(), nullptr, n, nhat, fs, f);
        const double un = s.u * nhat[0] + s.v * nhat[1] + s.w * nhat[2];
        const double c = std::sqrt(kGamma * s.p / s.rho);
        const double pstar = s.p + s.rho * un * (un + c);
        EXPECT_NEAR(f[0], 0.0, 1e-14);
        EXPECT_NEAR(f[4], 0.0, 1e-14);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(f[1 + a], pstar * n[a], 1e-14 * (1 + std::abs(pstar) * len));
        // The same for any tangential velocity: only u_n enters.
        Primitive t = s;
        t.u += 0.3 * (nhat[1] - nhat[2]);
        t.v += 0.3 * (nhat[2] - nhat[0]);
        t.w += 0.3 * (nhat[0] - nhat[1]);  // (1, 1, 1) x nhat, normal to nhat
        const auto qt = conservative(t);
        double g[5];
        slipWallFlux<double>(qt.data(), nullptr, n, nhat, fs, g);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(g[v], f[v], 1e-13 * (1 + std::abs(f[v])));
    }
}

TEST(SlipWall, ItsSatPenalizesTheNormalVelocityAndVanishesForFlowAlongTheWall) {
    std::mt19937 rng(5);
    const FreeStream fs;
    for (int trial = 0; trial < 30; ++trial) {
        Primitive s;
        double n[3];
        randomState(rng, 0.9, s, n);
        const double len = norm3(n), nhat[3] = {n[0] / len, n[1] / len, n[2] / len};
        const auto q = conservative(s);
        const auto fn = handFlux(q, n);
        double f[5];
        slipWallFlux<double>(q.data(), nullptr, n, nhat, fs, f);
        // SAT = F* - F_n(q): mass row -rho U, energy row -rho H U (U = u . n, H the total enthalpy).
        const double U = s.u * n[0] + s.v * n[1] + s.w * n[2];
        const double H = (q[4] + s.p) / s.rho;
        EXPECT_NEAR(f[0] - fn[0], -s.rho * U, 1e-13);
        EXPECT_NEAR(f[4] - fn[4], -s.rho * H * U, 1e-12);

        // Remove the normal velocity: the wall then takes the interior's own flux (no SAT), also
        // at a junction where the face vector is tilted away from the shared wall normal.
        Primitive t = s;
        const double un = s.u * nhat[0] + s.v * nhat[1] + s.w * nhat[2];
        t.u -= un * nhat[0];
        t.v -= un * nhat[1];
        t.w -= un * nhat[2];
        const auto qt = conservative(t);
        const double tilt[3] = {n[0] + 0.1 * len, n[1] - 0.05 * len, n[2] + 0.08 * len};
        for (const double* face : {static_cast<const double*>(n), static_cast<const double*>(tilt)}) {
            const auto ft = handFlux(qt, face);
            double g[5];
            slipWallFlux<double>(qt.data(), nullptr, face, nhat, fs, g);
            for (int v = 0; v < 5; ++v) EXPECT_NEAR(g[v], ft[v], 1e-13 * (1 + std::abs(ft[v])));
        }
    }
}

// The entropy flux the wall lets out, w . F* - rho U (w the entropy variables; F* has momentum
// only, and w's momentum part is rho u / p), is rho^2 u_n^2 (u_n + c) |n| / p: never negative
// while u_n > -c (the header's "entropy stable for u_n > -c"), negative for a flow leaving the
// wall faster than sound.
TEST(SlipWall, ProducesEntropyExactlyWhileTheNormalVelocityExceedsMinusTheSoundSpeed) {
    const FreeStream fs;
    const double n[3] = {0.6, -1.2, 0.4};
    const double len = norm3(n), nhat[3] = {n[0] / len, n[1] / len, n[2] / len};
    const Primitive base{1.2, 0.3, 0.1, -0.2, 0.9 / kGamma};
    const double c = std::sqrt(kGamma * base.p / base.rho);
    for (double fraction : {-1.5, -1.1, -0.9, -0.5, -0.1, 0.0, 0.2, 0.8, 1.3}) {
        // Set u . nhat = fraction * c, keeping the tangential velocity.
        Primitive s = base;
        const double un0 = s.u * nhat[0] + s.v * nhat[1] + s.w * nhat[2];
        const double un = fraction * c;
        s.u += (un - un0) * nhat[0];
        s.v += (un - un0) * nhat[1];
        s.w += (un - un0) * nhat[2];
        const auto q = conservative(s);
        double f[5];
        slipWallFlux<double>(q.data(), nullptr, n, nhat, fs, f);
        const double U = un * len;
        const double entropyFlux = (q[1] * f[1] + q[2] * f[2] + q[3] * f[3]) / s.p - s.rho * U;
        const double expected = s.rho * s.rho * un * un * (un + c) * len / s.p;
        EXPECT_NEAR(entropyFlux, expected, 1e-13) << "u_n / c = " << fraction;
        if (fraction > -1.0) {
            EXPECT_GE(entropyFlux, -1e-15) << "u_n / c = " << fraction;
        } else {
            EXPECT_LT(entropyFlux, 0.0) << "u_n / c = " << fraction;
        }
    }
}

// The header calls the wall flux the upwind flux against the mirror state (u_n reversed) in
// closed form. Worked out by hand, that upwind flux is (0, (p + rho u_n (u_n + c_m)) n, 0) with
// c_m the sound speed of the mean of the two states (pressure p + (gamma-1)/2 rho u_n^2); the
// closed form takes the interior's c instead, so the two agree to O(u_n^3).
TEST(SlipWall, AgreesWithTheUpwindFluxAgainstTheMirrorStateToThirdOrder) {
    const FreeStream fs;
    const double n[3] = {0.0, 0.0, 1.5}, nhat[3] = {0.0, 0.0, 1.0};
    std::vector<double> differences;
    for (double un : {0.2, 0.1, 0.05}) {
        const Primitive s{0.9, 0.25, -0.1, un, 1.1 / kGamma};
        const auto q = conservative(s);
        const auto mirror = conservative(Primitive{s.rho, s.u, s.v, -un, s.p});
        double wall[5], upwind[5];
        slipWallFlux<double>(q.data(), nullptr, n, nhat, fs, wall);
        upwindFlux(q.data(), mirror.data(), n, kGamma, upwind);
        const double cm = std::sqrt(kGamma * (s.p + 0.5 * (kGamma - 1.0) * s.rho * un * un) / s.rho);
        EXPECT_NEAR(upwind[3], (s.p + s.rho * un * (un + cm)) * n[2], 1e-14);
        for (int v : {0, 1, 2, 4}) EXPECT_NEAR(upwind[v], 0.0, 1e-14);
        differences.push_back(std::abs(wall[3] - upwind[3]));
    }
    EXPECT_NEAR(differences[0] / differences[1], 8.0, 0.3);
    EXPECT_NEAR(differences[1] / differences[2], 8.0, 0.3);
}

TEST(SlipWall, CommutesWithRotations) {
    std::mt19937 rng(9);
    const FreeStream fs;
    for (int trial = 0; trial < 10; ++trial) {
        Primitive s;
        double n[3];
        randomState(rng, 1.2, s, n);
        const double len = norm3(n);
        const double nhat[3] = {n[0] / len, n[1] / len, n[2] / len};
        const Eigen::Matrix3d R = rotation(0.3 * trial, 1.0 - 0.2 * trial, 0.7 + 0.1 * trial);
        const Eigen::Vector3d rn = R * Eigen::Vector3d(n[0], n[1], n[2]);
        const Eigen::Vector3d rnhat = rn / rn.norm();
        const auto q = conservative(s);
        const auto rq = rotated(R, q);
        std::array<double, 5> f, g;
        slipWallFlux<double>(q.data(), nullptr, n, nhat, fs, f.data());
        slipWallFlux<double>(rq.data(), nullptr, rn.data(), rnhat.data(), fs, g.data());
        const auto rf = rotated(R, f);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(g[v], rf[v], 1e-13 * (1 + std::abs(rf[v])));
    }
}

// --- Symmetry plane ------------------------------------------------------------------------

TEST(Symmetry, HoldsAFreeStreamInTheXZPlaneOnEitherSide) {
    for (double alpha : {0.0, 4.0, -12.0}) {
        FreeStream fs;
        fs.mach = 0.8;
        fs.alphaDeg = alpha;
        const auto q = fs.state();
        for (double side : {1.0, -1.0}) {
            const double n[3] = {0.0, 2.5 * side, 0.0}, nhat[3] = {0.0, side, 0.0};
            double f[5];
            symmetryFlux<double>(q.data(), nullptr, n, nhat, fs, f);
            // F_n(q_inf) through a Y normal: only the pressure 1/gamma in the Y momentum.
            const double expected[5] = {0.0, 0.0, n[1] / kGamma, 0.0, 0.0};
            for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], expected[v], 1e-15) << "alpha " << alpha;
        }
    }
}

// The plane mirrors the normal velocity: reflecting the state in Y = 0 and looking from the
// other side (n -> -n) gives the reflected flux; a flow towards the plane (v n_y > 0) raises the
// pressure it carries by rho v^2 + rho |v| c, a flow away lowers it by rho |v| c - rho v^2.
TEST(Symmetry, MirrorsTheNormalVelocity) {
    const FreeStream fs;
    const double n[3] = {0.0, -1.7, 0.0}, nhat[3] = {0.0, -1.0, 0.0};
    const double mn[3] = {0.0, 1.7, 0.0}, mnhat[3] = {0.0, 1.0, 0.0};
    for (double v : {-0.4, -0.1, 0.0, 0.15, 0.5}) {
        const Primitive s{1.05, 0.45, v, 0.12, 0.95 / kGamma};
        const Primitive r{s.rho, s.u, -v, s.w, s.p};
        const auto q = conservative(s), qr = conservative(r);
        double f[5], g[5];
        symmetryFlux<double>(q.data(), nullptr, n, nhat, fs, f);
        symmetryFlux<double>(qr.data(), nullptr, mn, mnhat, fs, g);
        const double c = std::sqrt(kGamma * s.p / s.rho);
        const double un = -v;  // u . nhat
        const double pstar = s.p + s.rho * un * (un + c);
        EXPECT_NEAR(f[2], pstar * n[1], 1e-14) << "v " << v;
        for (int k : {0, 1, 3, 4}) {
            EXPECT_NEAR(f[k], 0.0, 1e-15);
            EXPECT_NEAR(g[k], 0.0, 1e-15);
        }
        EXPECT_NEAR(g[2], -f[2], 1e-14) << "v " << v;  // the reflection of (0, p* n, 0)
    }
}

// --- Farfield ------------------------------------------------------------------------------

TEST(Farfield, TheFreeStreamGetsItsOwnFluxInEveryRegime) {
    const double normals[][3] = {{1.0, 0.0, 0.0}, {-2.0, 0.5, 0.3}, {0.1, -0.2, 3.0}, {0.0, 1e-3, 0.0}};
    for (const FreeStream fs : {FreeStream{0.3, 0.0, 1.4}, FreeStream{0.85, -4.0, 1.4}, FreeStream{2.0, 10.0, 1.4}}) {
        const auto q = fs.state();
        const double a = fs.alpha(), M = fs.mach;
        for (const auto& n : normals) {
            // By hand: rho 1, u = M (cos a, 0, sin a), p = 1/gamma, rho E + p = 1/(gamma-1) + M^2/2.
            const double U = M * (std::cos(a) * n[0] + std::sin(a) * n[2]);
            const double expected[5] = {U, M * std::cos(a) * U + n[0] / kGamma, n[1] / kGamma,
                                        M * std::sin(a) * U + n[2] / kGamma, (1.0 / (kGamma - 1.0) + 0.5 * M * M) * U};
            double f[5], e[5];
            farfieldFlux<double>(q.data(), nullptr, n, n, fs, f);
            entropyFarfieldFlux<double>(q.data(), nullptr, n, n, fs, e);
            for (int v = 0; v < 5; ++v) {
                EXPECT_NEAR(f[v], expected[v], 1e-14 * (1 + std::abs(expected[v]))) << "Mach " << M;
                EXPECT_NEAR(e[v], expected[v], 1e-14 * (1 + std::abs(expected[v]))) << "Mach " << M;
            }
        }
    }
}

// Linearized about the free stream, the farfield flux is A^+ = X max(Lambda, 0) X^-1 in the
// interior state: the outgoing characteristics (positive eigenvalues of A = dF_n/dq) come from
// inside, the incoming ones from the free stream (their interior perturbations have no effect).
// With a_inf = 1 the eigenvalues are U (three times) and U +- |n|, U = u_inf . n.
TEST(Farfield, TakesTheIncomingCharacteristicsFromTheFreeStream) {
    struct Regime {
        const char* name;
        double mach;
        double n[3];
        int incoming;
    };
    const double s = 1.7, c30 = std::cos(3.14159265358979323846 / 6), s30 = 0.5;
    const Regime regimes[] = {
        {"subsonic inflow", 0.5, {-s * c30, s * s30, 0.0}, 4},
        {"subsonic outflow", 0.5, {s * c30, 0.0, s * s30}, 1},
        {"supersonic inflow", 2.0, {-1.3, 0.0, 0.0}, 5},
        {"supersonic outflow", 2.0, {1.3, 0.2, 0.0}, 0},
    };
    for (const Regime& r : regimes) {
        FreeStream fs;
        fs.mach = r.mach;
        const auto qinf = fs.state();
        const Matrix5 J = complexStepJacobian(qinf, [&](const cplx* q, cplx* f) {
            const cplx n[3] = {r.n[0], r.n[1], r.n[2]};
            farfieldFlux<cplx>(q, nullptr, n, n, fs, f);
        });
        const Matrix5 A = complexStepJacobian(qinf, [&](const cplx* q, cplx* f) { handFlux(q, r.n, f); });
        const double U = r.mach * r.n[0], len = norm3(r.n);
        std::array<double, 5> expected = {std::max(U, 0.0), std::max(U, 0.0), std::max(U, 0.0),
                                          std::max(U + len, 0.0), std::max(U - len, 0.0)};
        std::sort(expected.begin(), expected.end());
        const auto lam = sortedEigenvalues(J);
        int zero = 0;
        for (int i = 0; i < 5; ++i) {
            EXPECT_NEAR(lam[i], expected[i], 1e-9) << r.name;
            zero += std::abs(lam[i]) < 1e-9;
        }
        EXPECT_EQ(zero, r.incoming) << r.name;
        // A^+ A^- = 0 with A^- = A - A^+: J is the projection onto the outgoing waves.
        EXPECT_LT((J * (A - J)).norm(), 1e-12 * (1 + A.squaredNorm())) << r.name;
        if (r.incoming == 5) {
            EXPECT_LT(J.norm(), 1e-13) << r.name;
        }
        if (r.incoming == 0) {
            EXPECT_LT((J - A).norm(), 1e-13 * A.norm()) << r.name;
        }
    }
}

// --- Interface -----------------------------------------------------------------------------

TEST(Interface, VanishesForAgreeingSidesAndTheTwoSidesSatsCancel) {
    std::mt19937 rng(13);
    const FreeStream fs;
    for (auto flux : {&interfaceFlux<double>, &entropyInterfaceFlux<double>}) {
        for (int trial = 0; trial < 30; ++trial) {
            Primitive a, b;
            double n[3], unused[3];
            randomState(rng, 1.8, a, n);
            randomState(rng, 1.8, b, unused);
            const auto qa = conservative(a), qb = conservative(b);
            // Same state on both sides: F* is the flux itself, so the SAT F* - F_n(q) is zero.
            const auto fn = handFlux(qa, n);
            double f[5];
            flux(qa.data(), qa.data(), n, n, fs, f);
            for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], fn[v], 1e-13 * (1 + std::abs(fn[v])));
            // Side b sees the outward vector -n: F*(qa, qb, n) + F*(qb, qa, -n) = 0, so the flux
            // leaving block a enters block b.
            const double mn[3] = {-n[0], -n[1], -n[2]};
            double g[5];
            flux(qa.data(), qb.data(), n, n, fs, f);
            flux(qb.data(), qa.data(), mn, mn, fs, g);
            for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v] + g[v], 0.0, 1e-13 * (1 + std::abs(f[v])));
        }
    }
}

// Linearized about a common state q, dF*/dqa = A^+ and dF*/dqb = A^- (each side supplies the
// waves that leave it), and the two add up to A = dF_n/dq.
TEST(Interface, UpwindsEachCharacteristicFromTheSideItLeaves) {
    std::mt19937 rng(17);
    const FreeStream fs;
    for (int trial = 0; trial < 10; ++trial) {
        Primitive s;
        double n[3];
        randomState(rng, trial < 5 ? 0.9 : 2.0, s, n);
        const auto q = conservative(s);
        const cplx nc[3] = {n[0], n[1], n[2]};
        const cplx qc[5] = {q[0], q[1], q[2], q[3], q[4]};
        const Matrix5 Ja = complexStepJacobian(q, [&](const cplx* x, cplx* f) { interfaceFlux<cplx>(x, qc, nc, nc, fs, f); });
        const Matrix5 Jb = complexStepJacobian(q, [&](const cplx* x, cplx* f) { interfaceFlux<cplx>(qc, x, nc, nc, fs, f); });
        const Matrix5 A = complexStepJacobian(q, [&](const cplx* x, cplx* f) { handFlux(x, n, f); });
        EXPECT_LT((Ja + Jb - A).norm(), 1e-12 * A.norm());
        const double U = s.u * n[0] + s.v * n[1] + s.w * n[2];
        const double cl = std::sqrt(kGamma * s.p / s.rho) * norm3(n);
        std::array<double, 5> plus, minus;
        const double lam[5] = {U, U, U, U + cl, U - cl};
        for (int i = 0; i < 5; ++i) {
            plus[i] = std::max(lam[i], 0.0);
            minus[i] = std::min(lam[i], 0.0);
        }
        std::sort(plus.begin(), plus.end());
        std::sort(minus.begin(), minus.end());
        const auto la = sortedEigenvalues(Ja), lb = sortedEigenvalues(Jb);
        for (int i = 0; i < 5; ++i) {
            EXPECT_NEAR(la[i], plus[i], 1e-8 * (1 + cl));
            EXPECT_NEAR(lb[i], minus[i], 1e-8 * (1 + cl));
        }
    }
}

// The entropy form's central part satisfies Tadmor's condition (w_b - w_a) . F_ec = rho_b U_b -
// rho_a U_a; its upwind part only removes entropy: (w_b - w_a) . F* <= rho_b U_b - rho_a U_a.
TEST(Interface, TheEntropyFormOnlyProducesEntropy) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const FreeStream fs;
    auto entropyVars = [](const std::array<double, 5>& q) {
        const double rho = q[0], u = q[1] / rho, v = q[2] / rho, w = q[3] / rho;
        const double p = (kGamma - 1.0) * (q[4] - 0.5 * rho * (u * u + v * v + w * w));
        const double s = std::log(p) - kGamma * std::log(rho);
        return std::array<double, 5>{(kGamma - s) / (kGamma - 1.0) - 0.5 * rho * (u * u + v * v + w * w) / p,
                                     rho * u / p, rho * v / p, rho * w / p, -rho / p};
    };
    double worst = -1e300;
    for (int trial = 0; trial < 60; ++trial) {
        Primitive a;
        double n[3];
        randomState(rng, 1.5, a, n);
        const double jump = trial < 30 ? 0.05 : 0.3;
        const Primitive b{a.rho * (1 + jump * U(rng)), a.u + jump * U(rng), a.v + jump * U(rng), a.w + jump * U(rng),
                          a.p * (1 + jump * U(rng))};
        const auto qa = conservative(a), qb = conservative(b);
        const auto wa = entropyVars(qa), wb = entropyVars(qb);
        double f[5];
        entropyInterfaceFlux<double>(qa.data(), qb.data(), n, n, fs, f);
        double dwF = 0;
        for (int v = 0; v < 5; ++v) dwF += (wb[v] - wa[v]) * f[v];
        const double psi = b.rho * (b.u * n[0] + b.v * n[1] + b.w * n[2]) - a.rho * (a.u * n[0] + a.v * n[1] + a.w * n[2]);
        EXPECT_LE(dwF - psi, 1e-13) << "trial " << trial;
        worst = std::max(worst, dwF - psi);
    }
    EXPECT_LT(worst, 0.0);
}

// --- Choice by name ------------------------------------------------------------------------

TEST(BoundaryFlux, IsChosenByNameKindAndScheme) {
    using mesh::BoundaryKind;
    EXPECT_EQ(boundaryFlux<double>("farfield"), &farfieldFlux<double>);
    EXPECT_EQ(boundaryFlux<double>("wall"), &slipWallFlux<double>);
    EXPECT_EQ(boundaryFlux<double>("symmetry"), &symmetryFlux<double>);
    EXPECT_EQ(boundaryFlux<double>("interface"), &interfaceFlux<double>);
    EXPECT_EQ(boundaryFlux<cplx>("interface"), &interfaceFlux<cplx>);
    for (BoundaryKind k : {BoundaryKind::Wall, BoundaryKind::Farfield, BoundaryKind::Symmetry, BoundaryKind::Interface}) {
        EXPECT_EQ(boundaryFlux<double>(k), boundaryFlux<double>(mesh::boundaryName(k)));
        EXPECT_EQ(boundaryFlux<double>(k, InviscidScheme::Central), boundaryFlux<double>(k));
    }
    const auto ec = InviscidScheme::EntropyConservative;
    EXPECT_EQ(boundaryFlux<double>(BoundaryKind::Farfield, ec), &entropyFarfieldFlux<double>);
    EXPECT_EQ(boundaryFlux<double>(BoundaryKind::Interface, ec), &entropyInterfaceFlux<double>);
    EXPECT_EQ(boundaryFlux<cplx>(BoundaryKind::Interface, ec), &entropyInterfaceFlux<cplx>);
    EXPECT_EQ(boundaryFlux<double>(BoundaryKind::Wall, ec), &slipWallFlux<double>);
    EXPECT_EQ(boundaryFlux<double>(BoundaryKind::Symmetry, ec), &symmetryFlux<double>);
}

TEST(BoundaryFlux, AnUnknownNameIsACaseErrorNamingTheKeyAndTheName) {
    for (const std::string name : {"inlet", "Wall", ""}) {
        try {
            (void)boundaryFlux<double>(name, "blocks[2].faces[4]");
            ADD_FAILURE() << "accepted '" << name << "'";
        } catch (const CaseError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("blocks[2].faces[4]"), std::string::npos) << m;
            EXPECT_NE(m.find("'" + name + "'"), std::string::npos) << m;
        }
    }
}
