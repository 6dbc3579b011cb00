#pragma once
// Grid metrics of the curvilinear transformation x(xi, eta, zeta), computed with the SBP
// operator D of Sbp.h in the conservative form of Thomas & Lombard (AIAA J 17(10), 1979):
//   xi_x / J = D_zeta(z D_eta y) - D_eta(z D_zeta y)       (and cyclically in (x, y, z) and in
//                                                           (xi, eta, zeta)),
// i.e. for direction d with the two others a = d+1, b = d+2 (mod 3) and component c with
// c1 = c+1, c2 = c+2 (mod 3):  m_d[c] = D_b(x_c2 D_a x_c1) - D_a(x_c2 D_b x_c1).
// Because the D's along different directions commute, sum_d D_d m_d = 0 holds discretely
// (geometric conservation), so a uniform flow is a discrete steady state on any grid.
#include <type_traits>
#include <vector>

#include "flow/Euler.h"
#include "flow/FlowMesh.h"

namespace aero::flow {

/// Values per node: m_xi (3), m_eta (3), m_zeta (3) (each grad(direction)/J), then 1/J.
constexpr int kMetricWidth = 10;
static_assert(std::is_same_v<MetricDual, Dual<kMetricWidth>>, "MetricDual: one direction per metric value");

/// metrics (kMetricWidth per node, global node order) from coordinates xyz (3 per node).
/// 1/J is (1/3) sum_d (D_d x) . m_d. Templated for complex step on the coordinates.
template <class T>
void computeMetrics(const FlowMesh& fm, const T* xyz, T* metrics);

std::vector<double> computeMetrics(const FlowMesh& fm, const std::vector<double>& xyz);

/// Smallest 1/J over all nodes and where it is (block, local node): a value <= 0 means a folded
/// or left-handed grid.
struct VolumeCheck {
    double minJinv = 0;
    int block = -1;
    long node = -1;
};
VolumeCheck checkVolumes(const FlowMesh& fm, const std::vector<double>& metrics);

}  // namespace aero::flow
