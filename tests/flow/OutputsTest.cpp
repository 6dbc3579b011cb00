// The flow's outputs (flow/Outputs.h) against closed-form answers on the half-sphere grid: the
// free stream gives no force, Cp 0, entropy 0 and its own Mach number everywhere; a uniform
// overpressure pushes the half-body onto its symmetry plane with Delta_p times the plane's disc;
// a pressure rising linearly with height gives Archimedes' force (weight of the displaced
// "fluid": -g times the half-ball's volume 2 pi / 3) and its moment about an offset point, each
// converging at second order under grid refinement (the SBP surface quadrature and metrics;
// measured: errors fall by 4.0 per refinement, 1.1 % of Archimedes' force at refine 0.25).
#include "flow/Outputs.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "FlowFixtures.h"
#include "flow/Residual.h"

using namespace aero;
using namespace aero::flow;
using namespace aero::flow::testing;

namespace {

const double kPi = std::numbers::pi;

// rho 1 and no velocity, pressure p(x, y, z) per node.
template <class P>
std::vector<double> restState(const FlowCase& c, double gamma, P p) {
    std::vector<double> q(kVars * static_cast<std::size_t>(c.fm.nodeCount));
    for (long n = 0; n < c.fm.nodeCount; ++n) {
        const double* x = &c.x[3 * n];
        q[kVars * n] = 1.0;
        q[kVars * n + 4] = p(x[0], x[1], x[2]) / (gamma - 1.0);
    }
    return q;
}

// The side of Y = 0 the half-body lies on (+1 or -1), from its wall nodes.
double bodySide(const FlowCase& c) {
    double s = 0;
    for (const WallNode& w : wallNodes(c.fm)) s += c.x[3 * w.node + 1];
    return s > 0 ? 1.0 : -1.0;
}

TEST(Outputs, FreeStreamGivesNoForceZeroCpAndEntropyAndItsOwnMach) {
    const FlowCase& c = halfSphere(0.5, 0.05, 5);
    FreeStream fs;
    fs.mach = 0.5;
    fs.alphaDeg = 1.2;
    const std::vector<double> q = freeStreamState(c.fm, fs);
    const ForceCoefficients f = integrateForces(c.fm, c.metrics, c.x, q, fs, ForceReference{kPi / 2, 1.0, {0, 0, 0}});
    for (double v : {f.CL, f.CD, f.CM, f.CY}) EXPECT_EQ(v, 0.0);
    for (double cp : pressureCoefficient(c.fm, q, fs)) ASSERT_NEAR(cp, 0.0, 1e-14);
    for (double s : entropy(c.fm, q, fs)) ASSERT_NEAR(s, 0.0, 1e-14);
    for (double m : machNumber(c.fm, q, fs.gamma)) ASSERT_NEAR(m, 0.5, 1e-14);
    const auto wall = surfacePressure(c.fm, q, fs);
    ASSERT_FALSE(wall.empty());
    for (const SurfaceSample& s : wall) ASSERT_NEAR(s.cp, 0.0, 1e-14);
}

TEST(Outputs, AUniformOverpressurePushesTheHalfBodyOntoItsPlaneWithTheDiscArea) {
    FreeStream fs;
    fs.mach = 0.5;
    const double dp = 0.1 * fs.pressure();
    const ForceReference ref{1.0, 1.0, {0, 0, 0}};
    std::vector<double> errors;
    for (double refine : {0.25, 0.5, 1.0}) {
        const FlowCase& c = halfSphere(refine, 0.05, 5);
        const auto q = restState(c, fs.gamma, [&](double, double, double) { return fs.pressure() + dp; });
        const ForceCoefficients f = integrateForces(c.fm, c.metrics, c.x, q, fs, ref);
        const double qs = fs.dynamicPressure();
        // Along the plane's normal: -side dp pi (the wall's normals sum to minus the closing disc's).
        EXPECT_NEAR(f.force[1] * qs / (-bodySide(c) * dp * kPi), 1.0, 2e-2) << "refine " << refine;
        // In the plane: nothing, by the body's symmetry, to round-off.
        EXPECT_NEAR(f.force[0] * qs / dp, 0.0, 1e-12);
        EXPECT_NEAR(f.force[2] * qs / dp, 0.0, 1e-12);
        errors.push_back(std::abs(f.force[1] * qs + bodySide(c) * dp * kPi));
    }
    // Second order in the grid spacing (refine doubles the nodes per direction).
    EXPECT_GT(std::log2(errors[0] / errors[1]), 1.9) << errors[0] << " " << errors[1];
    EXPECT_GT(std::log2(errors[1] / errors[2]), 1.9) << errors[1] << " " << errors[2];
}

TEST(Outputs, APressureRisingWithHeightGivesArchimedesForceAndMomentAtSecondOrder) {
    FreeStream fs;
    fs.mach = 0.5;
    const double g = 0.2 * fs.pressure();        // dp/dz; p stays positive over the wall (|z| <= 1)
    const double volume = 2.0 * kPi / 3.0;       // the half-ball of radius 1
    const double a = 0.5;                        // moment reference point (a, 0, 0)
    const ForceReference ref{kPi / 2, 1.0, {a, 0, 0}};
    const double qs = fs.dynamicPressure() * ref.area;
    std::vector<double> forceErrors, momentErrors;
    for (double refine : {0.25, 0.5, 1.0}) {
        const FlowCase& c = halfSphere(refine, 0.05, 5);
        const auto q = restState(c, fs.gamma, [&](double, double, double z) { return fs.pressure() + g * z; });
        const ForceCoefficients f = integrateForces(c.fm, c.metrics, c.x, q, fs, ref);
        // The force on the body is -grad p times the volume it displaces (the closing disc at
        // Y = 0 carries only a Y force, and none here: the mean of z over it is 0).
        const double Fz = f.force[2] * qs, Fx = f.force[0] * qs, Fy = f.force[1] * qs;
        EXPECT_NEAR(Fz / (-g * volume), 1.0, 2e-2) << "refine " << refine;
        EXPECT_NEAR(Fx / (g * volume), 0.0, 1e-12);
        EXPECT_NEAR(Fy / (g * volume), 0.0, 1e-12);
        // Every normal of a sphere passes through its centre: no moment about it, so about
        // (a, 0, 0) the moment is -(a, 0, 0) x F, whose Y component is a Fz. alpha 0: CL = CZ.
        const double My = f.moment[1] * qs * ref.length;
        EXPECT_NEAR(My / (-a * g * volume), 1.0, 2e-2) << "refine " << refine;
        EXPECT_NEAR(f.CM, f.moment[1], 0.0);
        EXPECT_NEAR(f.CL, f.force[2], 1e-15);
        EXPECT_NEAR(f.CD, f.force[0], 1e-15);
        forceErrors.push_back(std::abs(Fz + g * volume));
        momentErrors.push_back(std::abs(My + a * g * volume));
    }
    EXPECT_GT(std::log2(forceErrors[0] / forceErrors[1]), 1.9) << forceErrors[0] << " " << forceErrors[1];
    EXPECT_GT(std::log2(forceErrors[1] / forceErrors[2]), 1.9) << forceErrors[1] << " " << forceErrors[2];
    EXPECT_GT(std::log2(momentErrors[1] / momentErrors[2]), 1.9) << momentErrors[1] << " " << momentErrors[2];
}

}  // namespace
