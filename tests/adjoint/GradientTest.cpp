// The whole gradient (issue #16): flow adjoint, grid sensitivities, regeneration transpose, mesh
// adjoint and the FFD chain, as a directional derivative against centred differences of complete
// evaluations (shape, mesh movement, flow) on the small blended-wing grid, from a deformed design.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "RandomVector.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "mesh/Quality.h"
#include "study/Gradient.h"

using namespace aero;

namespace {

io::CaseFile tightCase() {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/bwb_flow.json");
    c.mesh.extrusion.refine = 0.3;
    c.mesh.elasticity.tolerance = 1e-14;      // differences of moves at eps 1e-6 need moves to 1e-14
    c.flow.newton.relativeTolerance = 1e-12;  // and flows to round-off (6e-13)
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    return c;
}

}  // namespace

TEST(Gradient, DirectionalDerivativeMatchesCentredDifferencesOfWholeEvaluations) {
    study::CaseEvaluator ev(tightCase(), study::loadGeometry(tightCase().geometry));
    std::vector<double> v = ev.caseValues();
    for (double& x : v) x *= 0.8;  // deformed, between the sphere and the sample
    const study::Evaluation e = ev.evaluate(v);
    ASSERT_TRUE(e.ok()) << e.message;
    study::GradientOptions o;
    o.functionals = {"CL", "CD", "CL/CD", "wall_mach"};  // wall_mach: the optimizer's max_wall_mach constraint
    o.wallMachRho = 50;
    o.wallMachReference = 0.9;
    o.cornerRatioRho = 50;  // the optimizer's grid-validity constraint, through the same mesh adjoint
    o.wallBendRho = 1000;   // and its wall-bend constraint
    const study::GradientResult g = study::computeGradient(ev, e, o);
    ASSERT_TRUE(g.ok) << g.message;
    ASSERT_EQ(g.functionals.size(), 6u);
    EXPECT_EQ(g.functionals[3].name, study::kWallMach);
    EXPECT_EQ(g.functionals[4].name, study::kCornerRatio);
    EXPECT_EQ(g.functionals[5].name, study::kWallBend);
    const adjoint::Functional machSum = adjoint::Functional::wallMachSum(o.wallMachRho, o.wallMachReference);
    auto smoothMach = [&](const study::FlowResult& fl) {
        return adjoint::wallMachSmoothMax(machSum, adjoint::functionalValue(machSum, fl.mesh, fl.metrics, fl.x, fl.q,
                                                                            fl.residualOptions.freeStream,
                                                                            tightCase().flow.reference));
    };
    const std::vector<std::array<bool, 6>> walls = mesh::wallFaces(e.mesh->control);
    // With CL and CD requested, CL/CD comes from their adjoints (the quotient rule): two
    // adjoints (and the wall Mach number its own). Alone, CL/CD has its own adjoint (its
    // linearization, a combination of CL and CD): the same gradient to the adjoints' tolerance.
    ASSERT_EQ(g.adjoints.size(), 3u);
    study::GradientOptions alone;
    alone.functionals = {"CL/CD"};
    const study::GradientResult own = study::computeGradient(ev, e, alone);
    ASSERT_TRUE(own.ok) << own.message;
    ASSERT_EQ(own.adjoints.size(), 1u);
    for (const study::FunctionalGradient* R : {&g.functionals[2], &own.functionals[0]}) {
        ASSERT_EQ(R->name, "CL/CD");
        const study::FunctionalGradient &L = g.functionals[0], &D = g.functionals[1];
        EXPECT_NEAR(R->value, L.value / D.value, 1e-15 * std::abs(R->value));
        ASSERT_EQ(R->dv.size(), L.dv.size());
        double scale = 0, diff = 0;
        for (std::size_t i = 0; i < R->dv.size(); ++i) {
            const double q = (L.dv[i] * D.value - L.value * D.dv[i]) / (D.value * D.value);
            scale = std::max(scale, std::abs(q));
            diff = std::max(diff, std::abs(q - R->dv[i]));
        }
        EXPECT_LT(diff, 1e-7 * scale);
        EXPECT_NEAR(R->dalpha, (L.dalpha * D.value - L.value * D.dalpha) / (D.value * D.value),
                    1e-7 * std::abs(R->dalpha));
    }
    std::printf("gradient: linearization %.1f s, adjoint %.1f s, grid %.1f s, mesh %.1f s, chain %.2f s\n",
                g.secondsLinearization, g.secondsAdjoint, g.secondsGrid, g.secondsMesh, g.secondsChain);
    // A direction over all variables, scaled by their bounds.
    const std::vector<double> r = test::randomVector(v.size(), 3);
    std::vector<double> z(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const ffd::DesignVariable& dv = ev.model()->design().variables()[i];
        z[i] = r[i] * (dv.upper - dv.lower);
    }
    // The response is only piecewise smooth (the dissipation's switches: max, |.|), so centred
    // differences have a first-order error once eps crosses a switch (measured: at eps 1e-4 / 1e-5
    // / 1e-6 they differed from the adjoint by 4e-4 / 2e-4 / 5e-8 on one grid), and where the
    // switches lie moves with the grid: as in the paper's check, the best of several steps counts.
    std::vector<std::pair<double, double>> ratios;  // (step, corner ratio) of every evaluation
    std::vector<double> bends;                      // and its wall bend
    std::vector<double> machs;                      // and its wall Mach number's smooth maximum
    auto at = [&](double s) {
        std::vector<double> w = v;
        for (std::size_t i = 0; i < v.size(); ++i) w[i] += s * z[i];
        study::Evaluation ee = ev.evaluate(w);
        EXPECT_TRUE(ee.ok()) << ee.message;
        ratios.emplace_back(s, mesh::cornerRatioSmoothMin(ee.mesh->grids, ev.baselineGrids(), o.cornerRatioRho));
        bends.push_back(mesh::wallBendSmoothMax(ee.mesh->grids, walls, o.wallBendRho));
        machs.push_back(smoothMach(*ee.flow));
        return ee.flow->forces;
    };
    double best[3] = {1e300, 1e300, 1e300}, bestFd[3] = {0, 0, 0}, exact[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        for (std::size_t i = 0; i < v.size(); ++i) exact[k] += g.functionals[k].dv[i] * z[i];
    }
    for (double eps : {1e-5, 1e-6, 1e-7}) {
        const flow::ForceCoefficients p = at(eps), m = at(-eps);
        const double fd[3] = {(p.CL - m.CL) / (2 * eps), (p.CD - m.CD) / (2 * eps),
                              (p.CL / p.CD - m.CL / m.CD) / (2 * eps)};
        for (int k = 0; k < 3; ++k) {
            if (std::abs(fd[k] - exact[k]) < best[k]) {
                best[k] = std::abs(fd[k] - exact[k]);
                bestFd[k] = fd[k];
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        std::printf("%s: adjoint %.10g, centred difference %.10g\n", g.functionals[k].name.c_str(), exact[k], bestFd[k]);
        EXPECT_NEAR(exact[k], bestFd[k], 1e-6 * std::abs(bestFd[k])) << g.functionals[k].name;
    }
    // The grid's corner ratio: a smooth function of the design (no dissipation switches).
    EXPECT_NEAR(g.functionals[4].value, mesh::cornerRatioSmoothMin(e.mesh->grids, ev.baselineGrids(), 50), 1e-14);
    double ratioExact = 0;
    for (std::size_t i = 0; i < v.size(); ++i) ratioExact += g.functionals[4].dv[i] * z[i];
    double bestRatio = 1e300;
    for (std::size_t a = 0; a + 1 < ratios.size(); a += 2) {
        const double fd = (ratios[a].second - ratios[a + 1].second) / (2 * ratios[a].first);
        bestRatio = std::min(bestRatio, std::abs(fd - ratioExact));
    }
    std::printf("corner ratio: %.10g, directional derivative %.10g, best difference %.2e\n", g.functionals[4].value,
                ratioExact, bestRatio);
    EXPECT_LT(bestRatio, 1e-6 * std::abs(ratioExact));
    // The wall bend likewise (degrees; it depends on the wall grid alone).
    EXPECT_NEAR(g.functionals[5].value, mesh::wallBendSmoothMax(e.mesh->grids, walls, 1000), 1e-12);
    double bendExact = 0;
    for (std::size_t i = 0; i < v.size(); ++i) bendExact += g.functionals[5].dv[i] * z[i];
    double bestBend = 1e300;
    for (std::size_t a = 0; a + 1 < bends.size(); a += 2) {
        bestBend = std::min(bestBend, std::abs((bends[a] - bends[a + 1]) / (2 * ratios[a].first) - bendExact));
    }
    std::printf("wall bend: %.10g degrees, directional derivative %.10g, best difference %.2e\n", g.functionals[5].value,
                bendExact, bestBend);
    EXPECT_GT(std::abs(bendExact), 1e-3);
    EXPECT_LT(bestBend, 1e-6 * std::abs(bendExact));
    // The wall Mach number's smooth maximum: through the flow adjoint, like the forces (the best
    // of the steps, for the same reason), and its value is the flow's.
    EXPECT_NEAR(g.functionals[3].value, smoothMach(*e.flow), 1e-14);
    double machExact = 0;
    for (std::size_t i = 0; i < v.size(); ++i) machExact += g.functionals[3].dv[i] * z[i];
    double bestMach = 1e300, bestMachFd = 0;
    for (std::size_t a = 0; a + 1 < machs.size(); a += 2) {
        const double fd = (machs[a] - machs[a + 1]) / (2 * ratios[a].first);
        if (std::abs(fd - machExact) < bestMach) {
            bestMach = std::abs(fd - machExact);
            bestMachFd = fd;
        }
    }
    std::printf("wall Mach (smooth max): %.10g, adjoint %.10g, centred difference %.10g\n", g.functionals[3].value,
                machExact, bestMachFd);
    EXPECT_GT(std::abs(machExact), 1e-3);
    EXPECT_NEAR(machExact, bestMachFd, 1e-6 * std::abs(bestMachFd));
}

