// The gradient's geometry outputs (GradientOptions::geometrySensitivities): dJ/dB on the lattice
// points and dJ/dA on the geometry's control points, on the small blended-wing grid at the
// sample's deformed design:
//   - the chain closes: dJ/dv = (dB/dv)^T dJ/dB for every variable (ffd::DesignSpace::jacobian),
//     and dJ/dB = (dA/dB)^T dJ/dA;
//   - dJ/dB of the lattice coordinate with the largest sensitivity against a centred difference of
//     whole evaluations with that point displaced (a lattice drag's first-order prediction).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ffd/FfdModel.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Gradient.h"

using namespace aero;

namespace {

io::CaseFile smallBwb() {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/bwb_flow.json");
    c.mesh.extrusion.refine = 0.3;
    c.mesh.elasticity.increments = 2;
    c.mesh.elasticity.tolerance = 1e-14;      // differences of moves need moves to round-off
    c.flow.newton.relativeTolerance = 1e-12;  // and flows too
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    return c;
}

}  // namespace

TEST(GradientGeometry, LatticeAndControlPointSensitivitiesCloseTheChainAndMatchDifferences) {
    const io::CaseFile c = smallBwb();
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    ASSERT_NE(ev.model(), nullptr);
    const study::Evaluation e = ev.evaluate(ev.caseValues());
    ASSERT_TRUE(e.ok()) << e.message;
    study::GradientOptions o;
    o.functionals = {"CL/CD", "CD"};
    study::GradientResult plain = study::computeGradient(ev, e, o);
    ASSERT_TRUE(plain.ok) << plain.message;
    EXPECT_TRUE(plain.functionals[0].dLattice.empty());  // only when asked
    EXPECT_TRUE(plain.functionals[0].dUnique.empty());
    o.geometrySensitivities = true;
    const study::GradientResult g = study::computeGradient(ev, e, o);
    ASSERT_TRUE(g.ok) << g.message;
    const ffd::FfdModel& model = *ev.model();
    const std::size_t lattices = model.lattices().size();
    for (const study::FunctionalGradient& f : g.functionals) {
        ASSERT_EQ(f.dUnique.size(), 3 * static_cast<std::size_t>(model.index().uniqueCount())) << f.name;
        ASSERT_EQ(f.dLattice.size(), lattices) << f.name;
        // The same dJ/dv as without the option, bit for bit (the same arithmetic).
        const study::FunctionalGradient* q = plain.find(f.name);
        ASSERT_NE(q, nullptr);
        EXPECT_EQ(f.dv, q->dv) << f.name;
        // dJ/dv = sum over lattices of (dB/dv)^T dJ/dB.
        Eigen::VectorXd dv = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(f.dv.size()));
        for (std::size_t l = 0; l < lattices; ++l) {
            const ffd::Lattice& L = model.lattices()[l].lattice;
            ASSERT_EQ(f.dLattice[l].size(), L.points.size()) << f.name;
            const Eigen::SparseMatrix<double> J = model.design().jacobian(static_cast<int>(l));
            const Eigen::Map<const Eigen::VectorXd> dB(f.dLattice[l].data(), static_cast<Eigen::Index>(f.dLattice[l].size()));
            dv += J.transpose() * dB;
        }
        double scale = 0, diff = 0;
        for (std::size_t i = 0; i < f.dv.size(); ++i) {
            scale = std::max(scale, std::abs(f.dv[i]));
            diff = std::max(diff, std::abs(f.dv[i] - dv[static_cast<Eigen::Index>(i)]));
        }
        EXPECT_GT(scale, 0) << f.name;
        EXPECT_LT(diff, 1e-12 * scale) << f.name;
        // dJ/dB = (dA/dB)^T dJ/dA.
        for (std::size_t l = 0; l < lattices; ++l) {
            const auto W = ffd::sensitivity(model.lattices()[l].lattice, model.embeddings()[l]);
            const std::vector<int>& points = model.embeddings()[l].points;
            for (int comp = 0; comp < 3; ++comp) {
                Eigen::VectorXd gA(W.rows());
                for (Eigen::Index p = 0; p < W.rows(); ++p) gA[p] = f.dUnique[3 * static_cast<std::size_t>(points[static_cast<std::size_t>(p)]) + comp];
                const Eigen::VectorXd dB = W.transpose() * gA;
                for (Eigen::Index a = 0; a < dB.size(); ++a)
                    EXPECT_NEAR(dB[a], f.dLattice[l][3 * static_cast<std::size_t>(a) + comp], 1e-13 * (1 + std::abs(dB[a])));
            }
        }
    }

    // One lattice coordinate, the most sensitive one of CL/CD, against centred differences of
    // whole evaluations (displacements on top of the case's; the best of several steps, as the
    // dissipation's switches make the response only piecewise smooth: tests/adjoint/GradientTest).
    const study::FunctionalGradient& R = g.functionals[0];
    std::size_t best = 0;
    for (std::size_t a = 0; a < R.dLattice[0].size(); ++a)
        if (std::abs(R.dLattice[0][a]) > std::abs(R.dLattice[0][best])) best = a;
    const ffd::Lattice& L0 = model.lattices()[0].lattice;
    const int point = static_cast<int>(best / 3), axis = static_cast<int>(best % 3);
    const int nx = L0.count[0], ny = L0.count[1];
    io::DisplacementCase d;
    d.lattice = 0;
    d.index = {point % nx, (point / nx) % ny, point / (nx * ny)};
    ASSERT_EQ(L0.index(d.index[0], d.index[1], d.index[2]), point);
    auto ratioAt = [&](double s) {
        study::EvaluationRequest r;
        std::vector<io::DisplacementCase> moved = c.displacements;
        d.delta = {0, 0, 0};
        d.delta[static_cast<std::size_t>(axis)] = s;
        moved.push_back(d);
        r.displacements = moved;
        const study::Evaluation m = ev.evaluate(ev.caseValues(), r);
        EXPECT_TRUE(m.ok()) << m.message;
        return m.ok() ? m.flow->forces.CL / m.flow->forces.CD : 0.0;
    };
    double bestDiff = 1e300, bestFd = 0;
    for (double eps : {1e-5, 1e-6}) {
        const double fd = (ratioAt(eps) - ratioAt(-eps)) / (2 * eps);
        if (std::abs(fd - R.dLattice[0][best]) < bestDiff) {
            bestDiff = std::abs(fd - R.dLattice[0][best]);
            bestFd = fd;
        }
    }
    std::printf("dJ/dB of lattice point %d, axis %d: adjoint %.10g, centred difference %.10g\n", point, axis,
                R.dLattice[0][best], bestFd);
    EXPECT_NEAR(R.dLattice[0][best], bestFd, 1e-5 * std::abs(bestFd));
}
