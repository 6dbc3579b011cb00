#include "flow/Euler.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <complex>
#include <random>

#include "common/Error.h"
#include "flow/bc/BoundaryFlux.h"

using namespace aero;
using namespace aero::flow;
using cplx = std::complex<double>;

namespace {

// A random physical state with Mach number up to `maxMach`, and a random metric vector.
void randomState(std::mt19937& rng, double maxMach, double* q, double* n) {
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const double rho = 1.0 + 0.5 * U(rng), p = (1.0 + 0.5 * U(rng)) / 1.4;
    const double c = std::sqrt(1.4 * p / rho);
    double u[3] = {U(rng), U(rng), U(rng)};
    const double s = maxMach * c * std::abs(U(rng)) / std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (double& x : u) x *= s;
    q[0] = rho;
    for (int a = 0; a < 3; ++a) q[1 + a] = rho * u[a];
    q[4] = p / 0.4 + 0.5 * rho * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int a = 0; a < 3; ++a) n[a] = 3.0 * U(rng);
}

Eigen::Matrix<double, 5, 5> fluxJacobian(const double* q, const double* n) {
    Eigen::Matrix<double, 5, 5> A;
    const double h = 1e-30;
    for (int c = 0; c < 5; ++c) {
        cplx qc[5], nc[3] = {n[0], n[1], n[2]}, f[5];
        for (int v = 0; v < 5; ++v) qc[v] = q[v];
        qc[c] += cplx(0, h);
        normalFlux(qc, nc, 1.4, f);
        for (int v = 0; v < 5; ++v) A(v, c) = f[v].imag() / h;
    }
    return A;
}

}  // namespace

TEST(Euler, FreeStreamIsNondimensionalizedBySoundSpeedAndDensity) {
    FreeStream fs{0.5, 1.2, 1.4};
    const auto q = fs.state();
    EXPECT_DOUBLE_EQ(q[0], 1.0);
    EXPECT_NEAR(pressure(q.data(), 1.4), 1.0 / 1.4, 1e-15);
    EXPECT_NEAR(soundSpeed(q.data(), 1.4), 1.0, 1e-15);
    const auto u = fs.velocity();
    EXPECT_NEAR(std::hypot(u[0], u[2]), 0.5, 1e-15);
    EXPECT_EQ(u[1], 0.0);
    EXPECT_GT(u[2], 0.0);  // positive alpha: flow from below
}

TEST(Euler, AbsoluteJacobianMatchesEigendecomposition) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        double q[5], n[3];
        randomState(rng, trial < 20 ? 0.9 : 2.5, q, n);
        const Eigen::Matrix<double, 5, 5> A = fluxJacobian(q, n);
        // |A| = sign(A) A, sign(A) by the Newton iteration S <- (S + S^-1)/2 (robust to the
        // triple eigenvalue, unlike an eigenvector matrix).
        Eigen::Matrix<double, 5, 5> S = A;
        for (int it = 0; it < 100; ++it) {
            const Eigen::Matrix<double, 5, 5> next = 0.5 * (S + S.inverse());
            const double change = (next - S).norm();
            S = next;
            if (change < 1e-15 * S.norm()) break;
        }
        const Eigen::Matrix<double, 5, 5> absA = S * A;
        Eigen::EigenSolver<Eigen::Matrix<double, 5, 5>> es(A, false);
        const Eigen::Matrix<double, 5, 1> lam = es.eigenvalues().real();
        Eigen::Matrix<double, 5, 5> ours;
        for (int c = 0; c < 5; ++c) {
            double e[5] = {}, out[5];
            e[c] = 1.0;
            absJacobianProduct(q, n, e, 1.4, out);
            for (int v = 0; v < 5; ++v) ours(v, c) = out[v];
        }
        EXPECT_LT((ours - absA).norm(), 1e-11 * absA.norm()) << "trial " << trial;
        // The spectral radius is the largest |eigenvalue|.
        EXPECT_NEAR(spectralRadius(q, n, 1.4), lam.cwiseAbs().maxCoeff(), 1e-12 * lam.cwiseAbs().maxCoeff());
    }
}

TEST(Euler, UpwindFluxIsConsistentAndAntisymmetric) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 20; ++trial) {
        double qa[5], qb[5], n[3], m[3], fn[5], f[5], g[5];
        randomState(rng, 1.5, qa, n);
        randomState(rng, 1.5, qb, m);
        normalFlux(qa, n, 1.4, fn);
        upwindFlux(qa, qa, n, 1.4, f);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], fn[v], 1e-14 * (1 + std::abs(fn[v])));
        const double mn[3] = {-n[0], -n[1], -n[2]};
        upwindFlux(qa, qb, n, 1.4, f);
        upwindFlux(qb, qa, mn, 1.4, g);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], -g[v], 1e-14 * (1 + std::abs(f[v])));
    }
}

TEST(Euler, BoundaryFluxesByNameAndFreeStreamConsistency) {
    const FreeStream fs{0.5, 3.0, 1.4};
    const auto qinf = fs.state();
    const double n[3] = {0.3, -1.2, 0.7};
    double fn[5], f[5];
    normalFlux(qinf.data(), n, 1.4, fn);
    boundaryFlux<double>("farfield")(qinf.data(), nullptr, n, n, fs, f);
    for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], fn[v], 1e-15);
    boundaryFlux<double>("interface")(qinf.data(), qinf.data(), n, n, fs, f);
    for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], fn[v], 1e-15);
    // Walls and the symmetry plane pass pressure only; a flow along the wall satisfies them.
    const double nw[3] = {0.0, -2.0, 0.0}, nwhat[3] = {0.0, -1.0, 0.0};
    normalFlux(qinf.data(), nw, 1.4, fn);
    for (const char* name : {"wall", "symmetry"}) {
        boundaryFlux<double>(name)(qinf.data(), nullptr, nw, nwhat, fs, f);
        for (int v = 0; v < 5; ++v) EXPECT_EQ(f[v], fn[v]) << name;
    }
    // At a wall junction the face vector n is tilted from the wall's normal nhat: a flow along
    // the wall (u . nhat = 0) still has F* = F_n(q), mass and energy crossing the tilted face.
    const double nhat[3] = {0.6, 0.0, 0.8}, ntilt[3] = {0.7, 0.1, 0.75};
    const double rho = 1.1, u[3] = {0.8 * 0.4, 0.05, -0.6 * 0.4}, p = 0.7;
    const double qt[5] = {rho, rho * u[0], rho * u[1], rho * u[2],
                          p / 0.4 + 0.5 * rho * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])};
    normalFlux(qt, ntilt, 1.4, fn);
    slipWallFlux<double>(qt, nullptr, ntilt, nhat, fs, f);
    for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], fn[v], 1e-15) << v;
    EXPECT_GT(std::abs(fn[0]), 1e-3);
    EXPECT_EQ(boundaryFlux<double>(mesh::BoundaryKind::Wall), &slipWallFlux<double>);
    EXPECT_THROW(boundaryFlux<double>("inlet", "flow.boundary"), CaseError);
    try {
        boundaryFlux<cplx>("inlet", "flow.boundary");
    } catch (const CaseError& e) {
        EXPECT_NE(std::string(e.what()).find("flow.boundary"), std::string::npos);
    }
}

TEST(Euler, LogarithmicMeanIsAccurateAndComplexStepDifferentiableThroughEqualArguments) {
    for (double b : {1.0, 0.3, 7.0}) {
        for (double rel : {0.0, 1e-12, 1e-6, 1e-3, 0.0199, 0.0201, 0.3, 2.0}) {
            const double a = b * (1.0 + rel);
            // Reference in long double: (a - b) / ln(a / b) with ln(a / b) = log1p(rel), b at rel = 0.
            const long double la = a, lb = b, lr = (la - lb) / lb;
            const double ref = rel == 0.0 ? b : static_cast<double>((la - lb) / std::log1p(lr));
            EXPECT_NEAR(logMean(a, b), ref, 2e-15 * ref) << a << " " << b;
            EXPECT_EQ(logMean(a, b), logMean(b, a));
            // d/da of the log mean: (L - L^2 / a) / (a - b), whose limit at a = b is 1/2.
            const double h = 1e-30;
            const double d = logMean(cplx(a, h), cplx(b, 0.0)).imag() / h;
            const long double L = rel == 0.0 ? lb : (la - lb) / std::log1p(lr);
            const double dref = rel > 1e-5 ? static_cast<double>((L - L * L / la) / (la - lb)) : 0.5 - rel / 6.0 + rel * rel / 8.0;
            EXPECT_NEAR(d, dref, 1e-13) << a << " " << b;
        }
    }
}

TEST(Euler, EntropyConservativeFluxIsConsistentSymmetricAndConservesEntropy) {
    std::mt19937 rng(11);
    for (int t = 0; t < 200; ++t) {
        double qa[5], qb[5], n[3], nb[3];
        randomState(rng, 1.5, qa, n);
        randomState(rng, 1.5, qb, nb);
        double f[5], g[5], F[5];
        entropyConservativeFlux(qa, qb, n, 1.4, f);
        entropyConservativeFlux(qb, qa, n, 1.4, g);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], g[v], 1e-14 * (1.0 + std::abs(f[v])));
        // Tadmor's condition: (w_b - w_a) . F = psi_b - psi_a with psi = rho u . n.
        double wa[5], wb[5];
        entropyVariables(qa, 1.4, wa);
        entropyVariables(qb, 1.4, wb);
        double lhs = 0, scale = 0;
        for (int v = 0; v < 5; ++v) {
            lhs += (wb[v] - wa[v]) * f[v];
            scale += std::abs(wb[v] * f[v]) + std::abs(wa[v] * f[v]);
        }
        const double psi = (qb[1] * n[0] + qb[2] * n[1] + qb[3] * n[2]) - (qa[1] * n[0] + qa[2] * n[1] + qa[3] * n[2]);
        EXPECT_NEAR(lhs, psi, 1e-14 * scale);
        // Consistency: F_ec(q, q) = F_n(q).
        entropyConservativeFlux(qa, qa, n, 1.4, f);
        normalFlux(qa, n, 1.4, F);
        for (int v = 0; v < 5; ++v) EXPECT_NEAR(f[v], F[v], 1e-14 * (1.0 + std::abs(F[v])));
    }
}

TEST(Euler, EntropyVariablesAreTheGradientOfTheEntropyFunction) {
    // w = dU/dq for U = -rho s / (gamma - 1), by complex step.
    std::mt19937 rng(5);
    double q[5], n[3], w[5];
    randomState(rng, 0.8, q, n);
    entropyVariables(q, 1.4, w);
    for (int c = 0; c < 5; ++c) {
        cplx qc[5];
        for (int v = 0; v < 5; ++v) qc[v] = q[v];
        qc[c] += cplx(0, 1e-30);
        const cplx p = pressure(qc, 1.4);
        const cplx U = -qc[0] * (std::log(p) - 1.4 * std::log(qc[0])) / 0.4;
        EXPECT_NEAR(U.imag() / 1e-30, w[c], 1e-13 * (1.0 + std::abs(w[c])));
    }
}

// The grid sensitivities evaluate the residual in dual numbers with 10 directions: every boundary
// flux (both schemes) must give, per direction, the complex-step derivative. Directions: the
// face vector n (3), the surface normal nhat (3), this side's state (4 of 5); the other side's
// state equals this side's in the second trial so the logarithmic means meet equal arguments.
TEST(Euler, DualNumbersGiveTheComplexStepDerivativesOfEveryBoundaryFlux) {
    using D = MetricDual;
    std::mt19937 rng(5);
    const FreeStream fs{0.6, 2.0, 1.4};
    double q[5], qo[5], n[3], nh[3];
    for (int trial = 0; trial < 2; ++trial) {
        randomState(rng, 0.9, q, n);
        randomState(rng, 0.9, qo, nh);
        if (trial == 1) std::copy(q, q + 5, qo);
        auto value = [&](int dir) -> double& { return dir < 3 ? n[dir] : dir < 6 ? nh[dir - 3] : q[dir - 6]; };
        for (mesh::BoundaryKind kind : {mesh::BoundaryKind::Farfield, mesh::BoundaryKind::Wall,
                                        mesh::BoundaryKind::Symmetry, mesh::BoundaryKind::Interface}) {
            for (InviscidScheme scheme : {InviscidScheme::Central, InviscidScheme::EntropyConservative}) {
                D qd[5], qod[5], nd[3], nhd[3], fd[5];
                for (int v = 0; v < 5; ++v) qod[v] = qo[v];
                for (int dir = 0; dir < 10; ++dir) {
                    D& x = dir < 3 ? nd[dir] : dir < 6 ? nhd[dir - 3] : qd[dir - 6];
                    x = D::variable(value(dir), dir);
                }
                qd[4] = q[4];
                boundaryFlux<D>(kind, scheme)(qd, qod, nd, nhd, fs, fd);
                for (int dir = 0; dir < 10; ++dir) {
                    const double h = 1e-30;
                    cplx qc[5], qoc[5], nc[3], nhc[3], fc[5];
                    for (int v = 0; v < 5; ++v) qc[v] = q[v], qoc[v] = qo[v];
                    for (int c = 0; c < 3; ++c) nc[c] = n[c], nhc[c] = nh[c];
                    (dir < 3 ? nc[dir] : dir < 6 ? nhc[dir - 3] : qc[dir - 6]) += cplx(0.0, h);
                    boundaryFlux<cplx>(kind, scheme)(qc, qoc, nc, nhc, fs, fc);
                    for (int v = 0; v < 5; ++v) {
                        // Complex division rounds differently from real division.
                        EXPECT_NEAR(fd[v].v, fc[v].real(), 1e-15 * (1.0 + std::abs(fc[v].real())))
                            << "trial " << trial << " kind " << int(kind);
                        const double ref = fc[v].imag() / h;
                        EXPECT_NEAR(fd[v].d[dir], ref, 1e-13 * (1.0 + std::abs(ref)))
                            << "trial " << trial << " kind " << int(kind) << " direction " << dir << " flux " << v;
                    }
                }
            }
        }
    }
}
