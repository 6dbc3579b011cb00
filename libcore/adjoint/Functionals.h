#pragma once
// Aerodynamic functionals J(q; x, alpha) of a flow solution and their exact partial derivatives,
// the right-hand sides of the discrete adjoint (Section IV.B of the paper, Eq. 10). Every
// functional is a sum over the wall nodes of a share j_k(metrics, x, q) templated on the scalar
// (wallNodeShare), so complex step gives dJ/dq, dJ/dmetrics and dJ/dx exactly, and the flow
// adjoint, the grid sensitivities and the whole gradient treat them all alike:
//   CL, CD, CM, CY       the force and moment coefficients (through flow::wallNodeForce);
//   pressure mismatch    J = 1/2 sum_k (p_k - p_target,k)^2 dA_k, the inverse design's objective
//                        (Section IV.C.2), against a target pressure per wall node;
//   wall Mach sum        S = sum_k exp(rho (M_k^2 - M_ref^2) / (2 M_ref)) over the wall nodes' local
//                        Mach numbers: a Kreisselmeier-Steinhauser aggregate, whose smooth maximum
//                        (wallMachSmoothMax) is the optimizer's bound on the wall Mach number.
// Chosen by name ("CL", "CD", "CM", "CY", "pressure") so the case file and the optimizer refer to
// them; adding one is one entry of the table in Functionals.cpp and one case of wallNodeShare.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "flow/FlowMesh.h"
#include "flow/Outputs.h"

namespace aero::adjoint {

struct Functional {
    enum class Kind { CL, CD, CM, CY, PressureMismatch, ForceCombination, WallMachSum };
    Kind kind = Kind::CL;
    /// PressureMismatch: the target static pressure at every wall node, in flow::wallNodes order.
    std::shared_ptr<const std::vector<double>> targetPressure;
    /// ForceCombination: c_CL CL + c_CD CD + c_CM CM + c_CY CY. The linearization of a nonlinear
    /// function of the coefficients at a state (CL/CD: 1/CD and -CL/CD^2) has this form, so one
    /// adjoint gives its gradient where the quotient rule on CL and CD needs two.
    std::shared_ptr<const std::array<double, 4>> coefficients;
    /// WallMachSum: the aggregation's rho and M_ref.
    double rho = 0, machReference = 0;

    static const Functional CL, CD, CM, CY;
    static Functional pressureMismatch(std::vector<double> target);
    static Functional forceCombination(double cCL, double cCD, double cCM = 0, double cCY = 0);
    static Functional wallMachSum(double rho, double machReference);
    /// A force or moment coefficient, or a combination of them (a linear function of the wall
    /// force and moment).
    bool isForce() const { return kind != Kind::PressureMismatch && kind != Kind::WallMachSum; }
    friend bool operator==(const Functional& a, const Functional& b) {
        return a.kind == b.kind && a.targetPressure == b.targetPressure && a.coefficients == b.coefficients &&
               a.rho == b.rho && a.machReference == b.machReference;
    }
};
inline const Functional Functional::CL{Functional::Kind::CL, nullptr, nullptr, 0, 0};
inline const Functional Functional::CD{Functional::Kind::CD, nullptr, nullptr, 0, 0};
inline const Functional Functional::CM{Functional::Kind::CM, nullptr, nullptr, 0, 0};
inline const Functional Functional::CY{Functional::Kind::CY, nullptr, nullptr, 0, 0};

/// "CL" -> Functional::CL, ... (the force functionals); throws CaseError naming the choices for an
/// unknown name. "pressure" is not accepted here: it needs its target (Functional::pressureMismatch).
Functional functionalByName(const std::string& name);
const char* functionalName(const Functional& f);

/// A force functional as a linear function of the (unscaled) wall force F and moment M:
/// J = wF . F + wM . M (zero weights for the pressure mismatch and the wall Mach sum).
void functionalWeights(const Functional& f, const flow::FreeStream& fs, const flow::ForceReference& ref, double wF[3],
                       double wM[3]);

/// J's share at wall node w (the k-th entry of flow::wallNodes); metrics, x and q point at this
/// node's values. Throws GeometryError when a pressure target does not match the wall nodes.
template <class T>
T wallNodeShare(const Functional& f, const flow::WallNode& w, std::size_t k, const T* metrics, const T* x, const T* q,
                const flow::FreeStream& fs, const flow::ForceReference& ref);

/// J from the force coefficients (what flow::integrateForces gives); force functionals only.
double functionalValue(const Functional& f, const flow::ForceCoefficients& c);
/// J at a state: the sum of the wall-node shares (any functional).
double functionalValue(const Functional& f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                       const std::vector<double>& x, const std::vector<double>& q, const flow::FreeStream& fs,
                       const flow::ForceReference& ref);

/// dJ/dq at q: 5 values per node, global node order, exact to round-off.
std::vector<double> stateGradient(const Functional& f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const flow::FreeStream& fs, const flow::ForceReference& ref);

/// dJ/dalpha at fixed q, per degree of angle of attack (the lift and drag directions and the
/// moment axis rotate; the free stream's q_inf and p_inf, hence the pressure mismatch, and the
/// local Mach numbers do not).
double alphaPartial(const Functional& f, const flow::ForceCoefficients& c);

/// The local Mach number at every wall node (flow::wallNodes order).
std::vector<double> wallMach(const flow::FlowMesh& fm, const std::vector<double>& q, double gamma);

/// The smooth maximum of the wall Mach number that the wall Mach sum f stands for, S its value:
/// sqrt(M_ref^2 + 2 M_ref ln(S) / rho). It is at least the largest wall Mach number M_max, and
/// near M_ref at most about M_max + ln(number of wall nodes) / rho (only the nodes within a few
/// 1/rho of M_max count in practice). dS (optional): its derivative with respect to S.
double wallMachSmoothMax(const Functional& f, double S, double* dS = nullptr);

/// The static pressure at every wall node (flow::wallNodes order): an inverse design's target.
std::vector<double> wallPressure(const flow::FlowMesh& fm, const std::vector<double>& q, double gamma);

}  // namespace aero::adjoint
