// The paper's inverse design (Section IV.C.2, Figure 3b) on the small grid: 4 lattice control
// points of the half-sphere perturbed (samples/inverse_design_target.json), the target's wall
// pressure recorded, and the 12 coordinates recovered from the sphere by SLSQP with adjoint
// gradients through flow, grid, mesh movement and FFD: J down by >= 12 orders and every
// coordinate to 1e-6 (the paper: 18 orders in 29 evaluations).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/CaseFile.h"
#include "io/FlowFiles.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Optimization.h"

using namespace aero;

namespace {

io::CaseFile small(const std::string& name) {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/" + name);
    c.mesh.extrusion.refine = 0.3;  // 4,320 nodes
    c.mesh.elasticity.increments = 2;
    c.outputGeometry.clear();
    c.outputWallPressure.clear();
    return c;
}

}  // namespace

TEST(Optimization, InverseDesignRecoversThePerturbedLatticePoints) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/inverse_design";
    std::filesystem::create_directories(dir);
    // The target: the perturbed design's converged wall pressure.
    const io::CaseFile target = small("inverse_design_target.json");
    study::CaseEvaluator tev(target, study::loadGeometry(target.geometry));
    const study::Evaluation te = tev.evaluate(tev.caseValues());
    ASSERT_TRUE(te.ok()) << te.message;
    const std::string pressure = dir + "/target_pressure.csv";
    io::writeWallPressureCsv(pressure, te.flow->mesh, te.flow->x, te.flow->q, te.flow->residualOptions.freeStream);

    io::CaseFile c = small("inverse_design.json");
    c.optimization.optimizer = "slsqp";
    c.optimization.targetPressure = pressure;
    c.optimization.history = dir + "/history.csv";
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    double first = -1;
    o.onRecord = [&](const study::OptimizationRecord& r) {
        if (r.kind == study::OptimizationRecord::Kind::Values && r.ok && first < 0) first = r.J;
    };
    const study::OptimizationSummary s = study::optimizeCase(ev, o);
    std::printf("inverse design: %s after %d iterations, %d evaluations: J %.3e -> %.3e, optimality %.2e\n",
                optimize::statusName(s.result.status), s.result.iterations, s.result.evaluations, first, s.J,
                s.result.optimality);
    EXPECT_EQ(s.result.status, optimize::Status::Converged) << s.result.message;
    EXPECT_GT(first, 1e-7);
    EXPECT_LT(s.J, 1e-12 * first);
    EXPECT_LE(s.result.evaluations, 60);
    EXPECT_EQ(s.result.failedEvaluations, 0);
    const std::vector<ffd::DesignVariable>& vars = ev.model()->design().variables();
    ASSERT_EQ(vars.size(), 12u);
    for (std::size_t i = 0; i < vars.size(); ++i) {
        EXPECT_NEAR(s.values[i], target.values.at(vars[i].name), 1e-6) << vars[i].name;
    }
}
