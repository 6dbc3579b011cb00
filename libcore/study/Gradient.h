#pragma once
// Gradients of the case's functionals with respect to all design variables at an evaluated design:
// the discrete adjoint of the paper's Section IV.B through flow, grid regeneration, mesh movement
// and both FFD levels:
//   flow adjoint     (dR/dq)^T psi = -(dJ/dq)^T                       (adjoint/FlowAdjoint.h)
//   grid             g_x = dJ/dx + psi^T dR/dx                         (adjoint/GridSensitivity.h)
//   regeneration     g_b = N^T g_x                                     (mesh::regenerateTranspose)
//   mesh adjoint     g_A: the elasticity increments in reverse (Eq. 9) (mesh::moveControlGridAdjoint)
//   first level      dJ/dv = (dA/dB dB/dv)^T g_A                       (ffd::FfdModel::dUniqueDv)
//   angle of attack  dJ/dalpha = dJ/dalpha|_q + psi^T dR/dalpha
// One flow linearization serves every functional; a ratio (CL/CD) is differentiated as its
// linearization at the state, a combination of CL and CD: one adjoint, not two.
// The cost does not depend on the number of design variables.
#include <string>
#include <vector>

#include "adjoint/FlowAdjoint.h"
#include "mesh/Elasticity.h"
#include "study/CaseEvaluator.h"

namespace aero::study {

/// "CL", "CD", "CM", "CY" (adjoint::functionalByName), the ratio "CL/CD", the inverse design's
/// "pressure" (needs GradientOptions::targetPressure) or kWallMach (needs
/// GradientOptions::wallMachRho). Throws CaseError naming the choices for anything else.
void checkGradientFunctional(const std::string& name);

/// The name of the grid-validity function in GradientResult::functionals.
inline constexpr const char* kCornerRatio = "corner_ratio";
/// The name of the wall-bend function (mesh::wallBendSmoothMax, degrees) in GradientResult::functionals.
inline constexpr const char* kWallBend = "wall_bend";
/// The name of the wall Mach number's smooth maximum (adjoint::wallMachSmoothMax) in
/// GradientResult::functionals (requested with GradientOptions::wallMachRho).
inline constexpr const char* kWallMach = "wall_mach";
/// Its aggregation's rho (the optimizer's max_wall_mach constraint and the CLI's gradient).
inline constexpr double kWallMachRho = 50;

struct GradientOptions {
    std::vector<std::string> functionals{"CL", "CD"};
    std::vector<double> targetPressure;  // "pressure": the target per wall node (flow::wallNodes order)
    /// Also the gradient of the grid's smooth minimum corner ratio (mesh::cornerRatioSmoothMin
    /// against the baseline grid, at this rho; 0: not), named kCornerRatio in the result: the
    /// optimizer's grid-validity constraint, through the same mesh adjoint as the functionals.
    double cornerRatioRho = 0;
    /// Also the gradient of the wall's smooth sharpest bend (mesh::wallBendSmoothMax at this rho;
    /// 0: not), named kWallBend: the optimizer's constraint that keeps the shape resolved by the
    /// grid. The wall grid follows the surface alone, but it goes through the same chain.
    double wallBendRho = 0;
    /// With kWallMach among the functionals: the aggregation's rho and reference Mach number
    /// (adjoint::Functional::wallMachSum). Its gradient takes a flow adjoint of its own.
    double wallMachRho = 0, wallMachReference = 1.0;
    /// Also dJ/dA (FunctionalGradient::dUnique) and dJ/dB (FunctionalGradient::dLattice) of every
    /// requested functional: for a designer's view of where the geometry and the lattices should
    /// move (the optimizer does not need them).
    bool geometrySensitivities = false;
    adjoint::AdjointOptions adjoint;
};

struct FunctionalGradient {
    std::string name;
    double value = 0;
    std::vector<double> dv;  // per design variable (the evaluator's order)
    double dalpha = 0;       // per degree of angle of attack
    // With GradientOptions::geometrySensitivities (empty otherwise, and without lattices):
    std::vector<double> dUnique;               // dJ/dA = g_A: 3 per unique control point of the
                                               // geometry (the model's index() order)
    std::vector<std::vector<double>> dLattice; // dJ/dB = (dA/dB)^T g_A: per case lattice, 3 per
                                               // lattice control point (ffd::Lattice order); a
                                               // lattice point moved by dB changes J by dLattice . dB
};

struct GradientResult {
    bool ok = false;
    std::string message;  // the reason when not ok
    std::vector<FunctionalGradient> functionals;
    std::vector<adjoint::LinearSolveReport> adjoints;   // per adjoint solved (one per functional)
    mesh::MeshAdjointReport meshAdjoint;                // all base functionals at once
    double secondsLinearization = 0, secondsAdjoint = 0, secondsGrid = 0, secondsMesh = 0, secondsChain = 0;
    std::size_t historyBytes = 0;  // the forward move's stored increments
    double seconds() const {
        return secondsLinearization + secondsAdjoint + secondsGrid + secondsMesh + secondsChain;
    }
    const FunctionalGradient* find(const std::string& name) const;
};

/// The gradients at evaluation e (which must be ok, with mesh and flow stages run by ev).
/// Never throws for a linear solve that does not converge: the result says why.
GradientResult computeGradient(CaseEvaluator& ev, const Evaluation& e, const GradientOptions& o = {},
                               const Log& log = {});

}  // namespace aero::study
