#pragma once
// Aerodynamic functionals J(q; x, alpha) of a flow solution and their exact partial derivatives,
// the right-hand sides of the discrete adjoint (Section IV.B of the paper, Eq. 10):
//   dJ/dq (5 per node; non-zero on wall nodes only) by complex step through the templated
//   per-node force (flow::wallNodeForce), and dJ/dalpha at fixed q (the force projected on the
//   rotated lift and drag directions). Chosen by name ("CL", "CD", "CM", "CY") so the case file
//   and the optimizer can refer to them; adding one is one entry of the table in Functionals.cpp.
#include <string>
#include <vector>

#include "flow/FlowMesh.h"
#include "flow/Outputs.h"

namespace aero::adjoint {

enum class Functional { CL, CD, CM, CY };

/// "CL" -> Functional::CL, ...; throws CaseError naming the choices for an unknown name.
Functional functionalByName(const std::string& name);
const char* functionalName(Functional f);

/// J as a linear function of the (unscaled) wall force F and moment M: J = wF . F + wM . M.
void functionalWeights(Functional f, const flow::FreeStream& fs, const flow::ForceReference& ref, double wF[3],
                       double wM[3]);

/// J from the force coefficients (what flow::integrateForces gives).
double functionalValue(Functional f, const flow::ForceCoefficients& c);

/// dJ/dq at q: 5 values per node, global node order, exact to round-off.
std::vector<double> stateGradient(Functional f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const flow::FreeStream& fs, const flow::ForceReference& ref);

/// dJ/dalpha at fixed q, per degree of angle of attack (the lift and drag directions and the
/// moment axis rotate; the free stream's q_inf does not change with alpha).
double alphaPartial(Functional f, const flow::ForceCoefficients& c);

}  // namespace aero::adjoint
