#pragma once
// Functionals and fields of a flow solution: force and moment coefficients from the wall
// pressure integrated with the SBP norm (the same quadrature and the same pressure flux the wall
// SAT uses, so the forces are the discrete momentum flux into the walls), and nodal fields.
#include <array>
#include <vector>

#include "flow/Euler.h"
#include "flow/FlowMesh.h"

namespace aero::flow {

struct ForceReference {
    double area = 1.0;                   // S_ref (the half-body's, when a symmetry plane halves it)
    double length = 1.0;                 // c_ref for moments
    std::array<double, 3> point{0, 0, 0};  // moment reference point
};

struct ForceCoefficients {
    double CL = 0, CD = 0, CM = 0;  // lift (normal to the free stream in X-Z), drag (along it),
                                    // pitching moment about +Y (nose up for X downstream, Z up)
    double CY = 0;                  // side force (along Y)
    std::array<double, 3> force{};  // force coefficient vector F / (q_inf S)
    std::array<double, 3> moment{}; // moment coefficient vector M / (q_inf S c)
};

/// Integrates (p - p_inf) n_out over every wall face: F = sum_faces sum_nodes H_t1 H_t2 (p - p_inf)
/// n_out, n_out the outward metric vector of the fluid domain (into the body). x: 3 per node,
/// q: 5 per node, metrics: kMetricWidth per node.
/// A wall node of one block's wall face, with its SBP surface quadrature weight H_t1 H_t2.
struct WallNode {
    long node = 0;     // global node
    int face = 0;      // the block face (0..5) it lies on
    double weight = 0;
};
std::vector<WallNode> wallNodes(const FlowMesh& fm);

/// One wall node's contribution to the force (p - p_inf) n_out H and its moment about `point`
/// (not yet divided by q_inf S): metrics, x and q point at this node's values. Templated on the
/// scalar (double, std::complex<double>) so complex step differentiates the functionals.
template <class T>
void wallNodeForce(const WallNode& w, const T* metrics, const T* x, const T* q, const FreeStream& fs,
                   const std::array<double, 3>& point, T dF[3], T dM[3]);

ForceCoefficients integrateForces(const FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const FreeStream& fs, const ForceReference& ref);

/// Nodal fields (one value per node, global node order).
std::vector<double> pressureCoefficient(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs);
std::vector<double> machNumber(const FlowMesh& fm, const std::vector<double>& q, double gamma);
/// Entropy measure s = (p / rho^gamma) / (p_inf / rho_inf^gamma) - 1 (zero in the free stream and
/// in exact inviscid subsonic flow: any non-zero value is numerical error).
std::vector<double> entropy(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs);

/// Wall nodes with their surface Cp: block, local node, Cp (a node on several wall faces appears
/// once).
struct SurfaceSample {
    int block = 0;
    long node = 0;
    double cp = 0;
};
std::vector<SurfaceSample> surfacePressure(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs);

}  // namespace aero::flow
