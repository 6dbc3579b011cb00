// Linear modes of the pseudo-time flow dynamics (adjoint/FlowModes.h): the Arnoldi core against
// an operator with a known spectrum, the flow's modes against the exact Jacobian (each returned
// pair must satisfy J v = -mu D v), and the reason a solve that did not converge gets.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <complex>
#include <random>

#include "adjoint/FlowModes.h"
#include "flow/FlowSolver.h"
#include "flow/Jacobian.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

using namespace aero;

namespace {

// The blended-wing sample at Mach 0.5, alpha 1.2 on the small sampling of its grid (4,320 nodes).
io::CaseFile smallCase() {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/bwb_flow.json");
    c.mesh.extrusion.refine = 0.3;
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    return c;
}

}  // namespace

TEST(FlowModes, ArnoldiFindsTheDominantEigenpairsOfAnOperatorWithAKnownSpectrum) {
    // B: a rotation-scaling block (eigenvalues 0.9 +- 0.3i), a real 0.8, and the rest spread in
    // [-0.5, 0.5]; the operator is H B H with a Householder reflection H (not diagonal in the
    // basis Arnoldi starts from).
    const long n = 300;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double> u(n), diag(n);
    double uu = 0;
    for (long i = 0; i < n; ++i) {
        u[i] = uniform(rng);
        uu += u[i] * u[i];
        diag[i] = 0.5 * uniform(rng);
    }
    for (double& x : u) x /= std::sqrt(uu);
    diag[2] = 0.8;
    auto reflect = [&](std::vector<double>& x) {
        double s = 0;
        for (long i = 0; i < n; ++i) s += u[i] * x[i];
        for (long i = 0; i < n; ++i) x[i] -= 2 * s * u[i];
    };
    auto apply = [&](const double* in, double* out) {
        std::vector<double> x(in, in + n);
        reflect(x);
        std::vector<double> y(n);
        y[0] = 0.9 * x[0] - 0.3 * x[1];
        y[1] = 0.3 * x[0] + 0.9 * x[1];
        for (long i = 2; i < n; ++i) y[i] = diag[i] * x[i];
        reflect(y);
        std::copy(y.begin(), y.end(), out);
        return true;
    };
    std::vector<double> start(n);
    for (double& x : start) x = uniform(rng);
    const adjoint::RitzPairs r = adjoint::arnoldi(n, apply, start, 80);
    ASSERT_EQ(r.steps, 80);
    ASSERT_GE(r.values.size(), 3u);
    // Decreasing modulus: the pair first, then 0.8.
    EXPECT_NEAR(r.values[0].real(), 0.9, 1e-10);
    EXPECT_NEAR(std::abs(r.values[0].imag()), 0.3, 1e-10);
    EXPECT_NEAR(r.values[1].real(), 0.9, 1e-10);
    EXPECT_NEAR(r.values[0].imag(), -r.values[1].imag(), 1e-12);
    EXPECT_NEAR(r.values[2].real(), 0.8, 1e-10);
    EXPECT_NEAR(r.values[2].imag(), 0.0, 1e-12);
    // The residual estimate is the true residual ||op(v) - nu v|| of the unit Ritz vector.
    for (std::size_t k = 0; k < 3; ++k) {
        const std::vector<std::complex<double>> v = r.vector(k);
        std::vector<double> re(n), im(n), are(n), aim(n);
        double norm2 = 0;
        for (long i = 0; i < n; ++i) {
            re[i] = v[i].real();
            im[i] = v[i].imag();
            norm2 += std::norm(v[i]);
        }
        EXPECT_NEAR(norm2, 1.0, 1e-12);
        apply(re.data(), are.data());
        apply(im.data(), aim.data());
        double res = 0;
        for (long i = 0; i < n; ++i) res += std::norm(std::complex<double>(are[i], aim[i]) - r.values[k] * v[i]);
        EXPECT_NEAR(std::sqrt(res), r.residuals[k], 1e-11) << "pair " << k;
        EXPECT_LT(r.residuals[k], 1e-9);
    }
    // An operator that fails (an inner solve that did not converge) stops the iteration early.
    int calls = 0;
    const adjoint::RitzPairs partial = adjoint::arnoldi(
        n, [&](const double* in, double* out) { return ++calls <= 5 && apply(in, out); }, start, 80);
    EXPECT_EQ(partial.steps, 5);
    EXPECT_EQ(partial.values.size(), 5u);
}

TEST(FlowModes, TheFlowsModesAreEigenpairsOfTheExactJacobianAndDecayAtAConvergedState) {
    io::CaseFile c = smallCase();
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    const study::Evaluation e = ev.evaluate(ev.caseValues());
    ASSERT_TRUE(e.ok()) << e.message;
    const study::FlowResult& f = *e.flow;
    EXPECT_FALSE(f.modesChecked);  // converged: no analysis
    const adjoint::ModeReport rep = adjoint::pseudoTimeModes(f.mesh, f.metrics, f.q, f.residualOptions);
    EXPECT_TRUE(rep.failure.empty()) << rep.failure;
    EXPECT_EQ(rep.steps, 30);
    ASSERT_FALSE(rep.modes.empty());
    // The sample's steady state is stable: no mode grows (the slowest decays).
    EXPECT_EQ(rep.growing(), nullptr) << "rate " << rep.modes.front().rate;
    for (std::size_t k = 1; k < rep.modes.size(); ++k) {
        EXPECT_GE(rep.modes[k - 1].rate.real(), rep.modes[k].rate.real());
    }

    // A cancelled analysis stops before its first solve and says so.
    {
        std::atomic<bool> stop{true};
        adjoint::ModeOptions mo;
        mo.cancel = &stop;
        const adjoint::ModeReport cancelled = adjoint::pseudoTimeModes(f.mesh, f.metrics, f.q, f.residualOptions, mo);
        EXPECT_EQ(cancelled.failure, "cancelled");
        EXPECT_EQ(cancelled.steps, 0);
        EXPECT_TRUE(cancelled.modes.empty());
    }

    // Each pair against the exact Jacobian and D = V/dtau of CFL 1: J v + mu D v = 0, relative
    // to the size of either term (a wrong sign or scale of mu, or a wrong D, leaves O(1)).
    const long n = flow::kVars * f.mesh.nodeCount;
    flow::BlockSparseMatrix J = flow::jacobianPattern(f.mesh, flow::stencilRadius(f.residualOptions));
    flow::assembleJacobian(f.mesh, f.metrics, f.q.data(), f.residualOptions, J);
    const std::vector<double> d = flow::timeStepScale(f.mesh, f.metrics, f.q.data(), f.residualOptions.freeStream.gamma);
    for (const adjoint::FlowMode& m : rep.modes) {
        ASSERT_EQ(static_cast<long>(m.vector.size()), n);
        std::vector<double> re(n), im(n), jre(n), jim(n);
        for (long i = 0; i < n; ++i) {
            re[i] = m.vector[i].real();
            im[i] = m.vector[i].imag();
        }
        J.mult(re.data(), jre.data());
        J.mult(im.data(), jim.data());
        double defect = 0, jv = 0, dv = 0;
        for (long i = 0; i < n; ++i) {
            const std::complex<double> Jv(jre[i], jim[i]);
            const std::complex<double> Dv = d[i / flow::kVars] * m.vector[i];
            defect += std::norm(Jv + m.rate * Dv);
            jv += std::norm(Jv);
            dv += std::norm(m.rate * Dv);
        }
        const double rel = std::sqrt(defect) / (std::sqrt(jv) + std::sqrt(dv));
        std::printf("mode %+.4e %+.4ei: Ritz residual %.1e, defect %.2e\n", m.rate.real(), m.rate.imag(), m.residual, rel);
        EXPECT_LE(m.residual, 1e-3);
        EXPECT_NEAR(rel, m.defect, 1e-8);
        // The Ritz vectors are rough where the spectrum clusters (FlowMode::defect), but a wrong
        // sign or scale of mu, or a wrong D, would leave a defect near 1.
        EXPECT_LT(rel, 0.2) << "mode rate " << m.rate;
        EXPECT_GT(m.share, 0);
        EXPECT_LE(m.share, m.regionShare);
        EXPECT_LE(m.regionShare, 1.0 + 1e-12);
        EXPECT_GE(m.node, 0);
        EXPECT_LT(m.node, f.mesh.nodeCount);
    }
}

TEST(FlowModes, ASolveThatDoesNotConvergeGetsTheModeAnalysisInItsReason) {
    io::CaseFile c = smallCase();
    c.flow.newton.maxIterations = 4;  // stopped early: not converged
    {
        study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
        const study::Evaluation e = ev.evaluate(ev.caseValues());
        ASSERT_EQ(e.status, study::EvaluationStatus::FlowNotConverged);
        const study::FlowResult& f = *e.flow;
        ASSERT_TRUE(f.modesChecked);
        EXPECT_GT(f.modes.steps, 0);
        EXPECT_GT(f.modes.linearIterations, 0);
        for (const adjoint::FlowMode& m : f.modes.modes) EXPECT_TRUE(m.vector.empty()) << "eigenvectors kept";
        if (const adjoint::FlowMode* g = f.modes.growing()) {
            EXPECT_NE(e.message.find("grows in pseudo time"), std::string::npos) << e.message;
            EXPECT_NE(e.message.find(f.modeAt.blockName), std::string::npos) << e.message;
            EXPECT_EQ(f.modeAt.block >= 0, true);
            EXPECT_GT(g->rate.real(), 0);
        } else if (f.modes.conclusive()) {
            EXPECT_NE(e.message.find("no mode of the linearized flow grows"), std::string::npos) << e.message;
        } else {
            EXPECT_NE(e.message.find("the mode analysis has no verdict"), std::string::npos) << e.message;
        }
        // A request overrides the case (an optimizer's step: optimization.stall_modes).
        study::EvaluationRequest off;
        off.stallModes = false;
        const study::Evaluation o = ev.evaluate(ev.caseValues(), off);
        ASSERT_EQ(o.status, study::EvaluationStatus::FlowNotConverged);
        EXPECT_FALSE(o.flow->modesChecked);
        EXPECT_EQ(o.message.find("pseudo time"), std::string::npos) << o.message;
        EXPECT_EQ(o.message.find("mode analysis"), std::string::npos) << o.message;
    }
    c.flow.stallModes = false;
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    const study::Evaluation e = ev.evaluate(ev.caseValues());
    ASSERT_EQ(e.status, study::EvaluationStatus::FlowNotConverged);
    EXPECT_FALSE(e.flow->modesChecked);
    EXPECT_EQ(e.message.find("pseudo time"), std::string::npos) << e.message;
    study::EvaluationRequest on;
    on.stallModes = true;
    const study::Evaluation checked = ev.evaluate(ev.caseValues(), on);
    EXPECT_TRUE(checked.flow->modesChecked);
}

// A mode analysis has a verdict only when it found a growing mode, or converged modes without a
// failed solve; otherwise its growth rate is NaN (empty in the sweep's and the optimizer's
// records), not the 0 of "none grows".
TEST(FlowModes, AnAnalysisWithoutAVerdictHasNoGrowthRate) {
    adjoint::ModeReport r;
    EXPECT_FALSE(r.conclusive());
    EXPECT_TRUE(std::isnan(r.growthRate()));
    adjoint::FlowMode decaying;
    decaying.rate = {-0.01, 0.0};
    r.modes.push_back(decaying);
    EXPECT_TRUE(r.conclusive());
    EXPECT_EQ(r.growthRate(), 0.0);
    r.failure = "GMRES reached only 0.1 in 60 iterations";
    EXPECT_FALSE(r.conclusive());
    EXPECT_TRUE(std::isnan(r.growthRate()));
    adjoint::FlowMode growing;
    growing.rate = {0.004, 0.01};
    r.modes.insert(r.modes.begin(), growing);
    EXPECT_TRUE(r.conclusive());  // a growing mode found before the failure still counts
    EXPECT_EQ(r.growthRate(), 0.004);
}
