#pragma once
// The semi-discrete Euler residual R(q, x) of the paper's Eq. 8: (1/J) dq/dt + R = 0, with
//   R = D_xi E^ + D_eta F^ + D_zeta G^          (SBP derivatives of the contravariant fluxes
//                                                E^ = F_n(q) with n = m_xi = grad(xi)/J, ...)
//     + dissipation (Dissipation.h)
//     + boundary SATs (bc/BoundaryFlux.h): (F*(q, .., n_out) - F_n_out(q)) / H_n at face nodes
//     + interface SATs: the same with F* = upwind flux against the coincident node's state.
// Layout: q and R hold 5 values per node (rho, rho u, rho v, rho w, rho E; Euler.h gives the
// nondimensionalization), [k][j][i][5] per block, blocks one after the other (FlowMesh offsets).
// Metrics come from computeMetrics (kMetricWidth per node, same node order).
// Templated on the scalar type; instantiated for double and std::complex<double>.
#include <vector>

#include "flow/Dissipation.h"
#include "flow/Euler.h"
#include "flow/FlowMesh.h"

namespace aero::flow {

/// Parts of the residual (for tests and diagnostics; the solver uses kAllTerms).
enum ResidualTerms : unsigned {
    kInviscid = 1u,
    kDissipation = 2u,
    kBoundarySat = 4u,   // farfield, wall, symmetry
    kInterfaceSat = 8u,
    kAllTerms = 15u,
};

struct ResidualOptions {
    FreeStream freeStream;
    InviscidScheme scheme = InviscidScheme::EntropyConservative;
    DissipationOptions dissipation;
    unsigned terms = kAllTerms;
    /// Preconditioner variant: lumped second-difference dissipation (7-point stencil).
    bool lumpedDissipation = false;
    /// Dissipation coefficients from the real part of q (constants under complex step).
    bool freezeCoefficients = false;
};

/// r = R(q) for all blocks (r is overwritten). q, r: 5 * fm.nodeCount; metrics:
/// kMetricWidth * fm.nodeCount. OpenMP over the blocks (each writes only its own nodes; the
/// loops inside a block run on one thread), then over the interface pairs.
/// `junctionNormals` (optional): the wall junctions' normals to use instead of computing them
/// from the metrics (the grid sensitivities hold them fixed and differentiate them apart).
template <class T>
void residual(const FlowMesh& fm, const T* metrics, const T* q, const ResidualOptions& o, T* r,
              const std::vector<T>* junctionNormals = nullptr);

/// dR/dalpha at fixed q and grid, per degree of angle of attack (5 * nodeCount). Only the
/// farfield SATs see alpha, through the free-stream state (the wall, symmetry and interface fluxes
/// use only gamma); their derivative is taken by complex step in that state: exact to round-off.
std::vector<double> alphaDerivative(const FlowMesh& fm, const std::vector<double>& metrics, const double* q,
                                    const ResidualOptions& o);

/// The free stream of `fs` at every node (5 * nodeCount).
std::vector<double> freeStreamState(const FlowMesh& fm, const FreeStream& fs);

/// Unit normals of the wall junctions (FlowMesh::wallJunctions), 3 per junction: the direction
/// of the sum of the members' outward metric vectors, second-order accurate on a smooth wall
/// (each member's own vector comes from one-sided differences at its block's edge and is tilted
/// by O(h); the two tilts cancel in the sum). Zeros for a geometric corner, where a member's
/// vector is more than 45 degrees from the sum's direction (a sharp trailing edge): there each
/// member keeps its own normal.
template <class T>
std::vector<T> wallJunctionNormals(const FlowMesh& fm, const T* metrics);

/// The unit normal nhat of the boundary surface that face f's flux uses at the face node with
/// position `index` in faceNodes order: the junction's normal for a wall junction node (unless
/// zero), n / |n| otherwise. n: the node's outward metric vector.
template <class T>
inline void surfaceNormal(const FlowBlock& blk, int f, long index, const T* n,
                          const std::vector<T>& junctionNormals, T* nhat) {
    using std::sqrt;
    if (blk.faces[f].kind == mesh::BoundaryKind::Wall && !blk.junction[f].empty()) {
        const int j = blk.junction[f][index];
        const T* jn = j >= 0 ? &junctionNormals[3 * static_cast<std::size_t>(j)] : nullptr;
        if (jn && (jn[0] != T(0.0) || jn[1] != T(0.0) || jn[2] != T(0.0))) {
            for (int c = 0; c < 3; ++c) nhat[c] = jn[c];
            return;
        }
    }
    const T len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int c = 0; c < 3; ++c) nhat[c] = n[c] / len;
}

/// Outward metric vector of face f at a node whose metrics are `m`: -m_d on a min face, +m_d on a
/// max face (d the face's direction).
template <class T>
inline void outwardNormal(const T* m, int f, T* n) {
    const int d = faceDirection(f);
    const double s = faceIsMax(f) ? 1.0 : -1.0;
    for (int c = 0; c < 3; ++c) n[c] = s * m[3 * d + c];
}

}  // namespace aero::flow
