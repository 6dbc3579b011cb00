// Grid sensitivities of the flow (issue #16): psi^T dR/dx and dJ/dx in reverse order through the
// metrics, against complex-step directional derivatives through the whole chain x -> metrics ->
// residual (with the wall junctions' normals) and x -> wall forces, on the small blended-wing
// grid (4,320 nodes: interfaces, wall junctions, a symmetry plane).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "RandomVector.h"
#include "adjoint/GridSensitivity.h"
#include "flow/Jacobian.h"
#include "flow/Metrics.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

using namespace aero;
using C = std::complex<double>;

namespace {

io::CaseFile smallCase() {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/bwb_flow.json");
    c.mesh.extrusion.refine = 0.3;
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    return c;
}

const study::Evaluation& state() {
    static const study::Evaluation e = [] {
        study::CaseEvaluator ev(smallCase(), study::loadGeometry(smallCase().geometry));
        // A deformed design, so no term vanishes by symmetry.
        std::vector<double> v = ev.caseValues();
        for (std::size_t i = 0; i < v.size(); ++i) v[i] *= 0.8;
        return ev.evaluate(v);
    }();
    return e;
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

// L(x + i h v) = J(q, x + i h v) + psi^T R(q, x + i h v), all in complex arithmetic.
double complexStepL(adjoint::Functional f, const study::FlowResult& r, const std::vector<double>& psi,
                    const std::vector<double>& v, const flow::ForceReference& ref, bool withJ) {
    const double h = 1e-30;
    const long N = r.mesh.nodeCount;
    std::vector<C> xc(3 * N), mc(flow::kMetricWidth * N), qc(r.q.begin(), r.q.end()), rc(5 * N);
    for (long i = 0; i < 3 * N; ++i) xc[i] = C(r.x[i], h * v[i]);
    flow::computeMetrics(r.mesh, xc.data(), mc.data());
    flow::residual(r.mesh, mc.data(), qc.data(), r.residualOptions, rc.data());
    double s = 0;
    for (long i = 0; i < 5 * N; ++i) s += psi[i] * rc[i].imag() / h;
    if (withJ && !f.isForce()) {
        const std::vector<flow::WallNode> wall = flow::wallNodes(r.mesh);
        for (std::size_t k = 0; k < wall.size(); ++k) {
            const flow::WallNode& w = wall[k];
            s += adjoint::wallNodeShare<C>(f, w, k, &mc[flow::kMetricWidth * w.node], &xc[3 * w.node], &qc[5 * w.node],
                                           r.residualOptions.freeStream, ref).imag() / h;
        }
    } else if (withJ) {
        double wF[3], wM[3];
        adjoint::functionalWeights(f, r.residualOptions.freeStream, ref, wF, wM);
        for (const flow::WallNode& w : flow::wallNodes(r.mesh)) {
            C dF[3], dM[3];
            flow::wallNodeForce(w, &mc[flow::kMetricWidth * w.node], &xc[3 * w.node], &qc[5 * w.node],
                                r.residualOptions.freeStream, ref.point, dF, dM);
            for (int c = 0; c < 3; ++c) s += (wF[c] * dF[c].imag() + wM[c] * dM[c].imag()) / h;
        }
    }
    return s;
}

}  // namespace

TEST(GridSensitivity, MetricTransposeIsTheTransposeOfTheMetricsDerivative) {
    const study::Evaluation& e = state();
    ASSERT_TRUE(e.ok()) << e.message;
    const study::FlowResult& r = *e.flow;
    const std::vector<double> gm = test::randomVector(r.metrics.size(), 3);
    const std::vector<double> v = test::randomVector(r.x.size(), 4);
    const std::vector<double> gx = adjoint::metricTranspose(r.mesh, r.x, gm);
    std::vector<C> xc(r.x.size()), mc(r.metrics.size());
    for (std::size_t i = 0; i < xc.size(); ++i) xc[i] = C(r.x[i], 1e-30 * v[i]);
    flow::computeMetrics(r.mesh, xc.data(), mc.data());
    double ref = 0;
    for (std::size_t i = 0; i < mc.size(); ++i) ref += gm[i] * mc[i].imag() / 1e-30;
    EXPECT_NEAR(dot(gx, v), ref, 1e-11 * std::abs(ref));
}

TEST(GridSensitivity, ResidualAndFunctionalGridGradientsMatchComplexStep) {
    const study::Evaluation& e = state();
    ASSERT_TRUE(e.ok()) << e.message;
    const study::FlowResult& r = *e.flow;
    ASSERT_FALSE(r.mesh.wallJunctions.empty());
    const flow::ForceReference ref = smallCase().flow.reference;
    const std::vector<double> psi = test::randomVector(r.q.size(), 7);
    // Residual part alone (dJ/dx off: psi^T dR/dx), then with each functional.
    for (int trial = 0; trial < 2; ++trial) {
        const std::vector<double> v = test::randomVector(r.x.size(), 11 + trial);
        const std::vector<double> gm = adjoint::residualMetricGradient(r.mesh, r.metrics, r.q, psi, r.residualOptions);
        const std::vector<double> gx = adjoint::metricTranspose(r.mesh, r.x, gm);
        const double exact = complexStepL(adjoint::Functional::CL, r, psi, v, ref, false);
        EXPECT_NEAR(dot(gx, v), exact, 1e-10 * std::abs(exact)) << "trial " << trial;
    }
    // The inverse design's pressure mismatch against a target that differs from the state by a
    // smooth field (its dJ/dx comes through the wall's area elements).
    std::vector<double> target = adjoint::wallPressure(r.mesh, r.q, r.residualOptions.freeStream.gamma);
    for (std::size_t k = 0; k < target.size(); ++k) target[k] += 0.01 * std::sin(0.1 * static_cast<double>(k));
    for (const adjoint::Functional& f : {adjoint::Functional::CL, adjoint::Functional::CD, adjoint::Functional::CM,
                                         adjoint::Functional::pressureMismatch(target),
                                         adjoint::Functional::wallMachSum(50, 0.9)}) {
        const std::vector<double> v = test::randomVector(r.x.size(), 21);
        const std::vector<double> zero(r.q.size(), 0.0);
        const std::vector<double> g =
            adjoint::coordinateGradient(f, zero, r.mesh, r.x, r.metrics, r.q, r.residualOptions, ref);
        const double exact = complexStepL(f, r, zero, v, ref, true);
        EXPECT_NEAR(dot(g, v), exact, 1e-10 * std::abs(exact)) << adjoint::functionalName(f);
    }
}
