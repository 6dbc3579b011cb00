// Experiment: GMRES iterations of the flow's linear systems at a converged state under several
// preconditioners (not a benchmark; prints a table).
//   linear_study CASE.json REFINE
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "adjoint/FlowAdjoint.h"
#include "adjoint/Functionals.h"
#include "flow/BlockIlu.h"
#include "flow/FlowSolver.h"
#include "flow/Gmres.h"
#include "flow/Jacobian.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

using namespace aero;

namespace {
double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: linear_study CASE.json REFINE\n");
        return 2;
    }
    io::CaseFile c = io::readCase(argv[1]);
    c.mesh.extrusion.refine = std::stod(argv[2]);
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    auto t0 = std::chrono::steady_clock::now();
    study::Evaluation e = ev.evaluate(ev.caseValues());
    std::printf("flow: %s, %d iterations, %d GMRES, %.1f s\n", e.message.c_str(), e.flow->report.iterations,
                e.flow->report.linearIterations, since(t0));
    const study::FlowResult& f = *e.flow;
    const flow::FlowMesh& fm = f.mesh;
    const long n = flow::kVars * fm.nodeCount;
    const flow::ResidualOptions& o = f.residualOptions;

    t0 = std::chrono::steady_clock::now();
    flow::BlockSparseMatrix J = flow::jacobianPattern(fm, flow::stencilRadius(o));
    flow::assembleJacobian(fm, f.metrics, f.q.data(), o, J);
    J.prepareTranspose();
    std::printf("exact Jacobian: %.2f s\n", since(t0));
    std::vector<double> g = adjoint::stateGradient(adjoint::Functional{}, fm, f.metrics, f.x, f.q,
                                                   o.freeStream, c.flow.reference);
    for (double& v : g) v = -v;

    struct Variant {
        double lumping;
        int fill;
        int parts;
        double cfl;
    };
    const Variant variants[] = {{3, 1, 2, 1e6}, {3, 1, 1, 1e6}, {3, 2, 2, 1e6}, {3, 3, 2, 1e6},
                                {2, 2, 2, 1e6}, {4, 2, 2, 1e6}, {6, 2, 2, 1e6}, {3, 0, 2, 1e6},
                                {3, 1, 2, 1e3}, {3, 2, 2, 1e3}};
    const int restartArg = argc > 3 ? std::stoi(argv[3]) : 60;
    const int deflationArg = argc > 5 ? std::stoi(argv[5]) : 0;
    const int only = argc > 4 ? std::stoi(argv[4]) : -1;
    int index = -1;
    for (const Variant& v : variants) {
        ++index;
        if (only >= 0 && index != only) continue;
        flow::ResidualOptions approx = o;
        approx.lumpedDissipation = true;
        approx.freezeCoefficients = true;
        approx.dissipation.lumping = v.lumping;
        flow::BlockSparseMatrix P = flow::jacobianPattern(fm, 1);
        flow::assembleApproximateJacobian(fm, f.metrics, f.q.data(), approx, P);
        std::vector<double> d = flow::timeStepScale(fm, f.metrics, f.q.data(), o.freeStream.gamma);
        for (double& x : d) x /= v.cfl;
        P.addDiagonal(d.data());
        flow::BlockIlu ilu;
        if (v.parts > 1) ilu.setOrdering(flow::partitionOrdering(P, flow::blockGroups(fm, v.parts), v.parts));
        auto t1 = std::chrono::steady_clock::now();
        if (!ilu.factor(P, v.fill)) {
            std::printf("sigma %g fill %d parts %d cfl %g: factor failed %s\n", v.lumping, v.fill, v.parts, v.cfl,
                        ilu.message().c_str());
            continue;
        }
        const double tf = since(t1);
        for (int transpose = 0; transpose < 2; ++transpose) {
            // The system at the pseudo-time diagonal too (a Newton step at this CFL) for the forward.
            const flow::LinearMap A = [&](const double* in, double* out) {
                if (transpose) {
                    J.multTranspose(in, out);
                } else {
                    J.mult(in, out);
                }
            };
            const flow::LinearMap M = [&](const double* in, double* out) {
                if (transpose) {
                    ilu.solveTranspose(in, out);
                } else {
                    ilu.solve(in, out);
                }
            };
          for (const auto& [restart, deflation] : std::vector<std::pair<int, int>>{{restartArg, deflationArg}, {60, 20}, {100, 30}}) {
            if (restart == 0) continue;
            std::vector<double> x(n, 0.0);
            t1 = std::chrono::steady_clock::now();
            const flow::GmresReport r = flow::gmres(n, A, M, g.data(), x.data(), {restart, 3000, 1e-10, 0.0, deflation});
            std::printf("restart %d deflation %d sigma %g fill %d parts %d cfl %g %s: %4d GMRES to %.1e, %.2f s (factor %.2f s, %ld blocks)\n",
                        restart, deflation, v.lumping, v.fill, v.parts, v.cfl, transpose ? "adjoint" : "tangent", r.iterations,
                        r.relativeResidual, since(t1), tf, ilu.storedBlocks());
            std::fflush(stdout);
          }
        }
    }
    return 0;
}
