#pragma once
// Grid sensitivities of the flow (the paper's Eq. 10, the term psi^T dR/dx + dJ/dx): the gradient
// of L(x) = J(q, x) + psi^T R(q, x) with respect to the grid coordinates x at a fixed, converged
// state q, in reverse order through the chain x -> metrics m -> (R, J):
//   g_m = psi^T dR/dm + dJ/dm    coloured forward mode on the metrics: the residual in dual
//                                numbers (common/Dual.h) with the 10 metric values of every node
//                                of one colour seeded as 10 directions (the residual reaches the
//                                metrics of the nodes within 2 along each grid line, the same
//                                13-point star as the state, so the Jacobian's 13-colour
//                                colouring separates them), with the wall junctions' normals held
//                                fixed; their own dependence on the members' metrics is
//                                differentiated apart (analytically: nhat = s / |s|);
//   g_x = (dm/dx)^T g_m + dJ/dx  coloured forward mode on the coordinates (a node's metrics reach
//                                the coordinates within one node in every direction of its block:
//                                27 colours, 3 directions each).
// Exact to round-off (no finite differences); the cost does not depend on the number of design
// variables: 13 residuals with 10 directions and 27 metric evaluations with 3 (they replaced 130
// complex residuals and 81 complex metric evaluations: 9.0 s -> 3.2 s on the 98k grid).
#include <vector>

#include "adjoint/Functionals.h"
#include "flow/FlowMesh.h"
#include "flow/Outputs.h"
#include "flow/Residual.h"

namespace aero::adjoint {

/// g_m = psi^T dR/dm at fixed q: flow::kMetricWidth values per node (global node order).
std::vector<double> residualMetricGradient(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                           const std::vector<double>& q, const std::vector<double>& psi,
                                           const flow::ResidualOptions& o);

/// The same for several adjoints at once (the complex residuals are shared).
std::vector<std::vector<double>> residualMetricGradients(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                                         const std::vector<double>& q,
                                                         const std::vector<std::vector<double>>& psis,
                                                         const flow::ResidualOptions& o);

/// g_x = (dm/dx)^T g_m: 3 values per node, from g_m (kMetricWidth per node) at coordinates x.
std::vector<double> metricTranspose(const flow::FlowMesh& fm, const std::vector<double>& x,
                                    const std::vector<double>& gm);
std::vector<std::vector<double>> metricTransposes(const flow::FlowMesh& fm, const std::vector<double>& x,
                                                  const std::vector<std::vector<double>>& gms);

/// Adds dJ/dm (into gm) and the direct dJ/dx (into gx, the moment arm) of functional f at
/// fixed q.
void addFunctionalGridGradient(Functional f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                               const std::vector<double>& x, const std::vector<double>& q,
                               const flow::FreeStream& fs, const flow::ForceReference& ref,
                               std::vector<double>& gm, std::vector<double>& gx);

/// dL/dx = dJ/dx + psi^T dR/dx at fixed q (3 values per node), for functional f with adjoint psi.
std::vector<double> coordinateGradient(Functional f, const std::vector<double>& psi, const flow::FlowMesh& fm,
                                       const std::vector<double>& x, const std::vector<double>& metrics,
                                       const std::vector<double>& q, const flow::ResidualOptions& o,
                                       const flow::ForceReference& ref);
/// The same for several functionals with their adjoints (one coloured sweep for all).
std::vector<std::vector<double>> coordinateGradients(const std::vector<Functional>& fs,
                                                     const std::vector<std::vector<double>>& psis,
                                                     const flow::FlowMesh& fm, const std::vector<double>& x,
                                                     const std::vector<double>& metrics, const std::vector<double>& q,
                                                     const flow::ResidualOptions& o, const flow::ForceReference& ref);

}  // namespace aero::adjoint
