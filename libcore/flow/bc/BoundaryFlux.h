#pragma once
// Boundary conditions of the Euler residual as numerical fluxes, all with one signature and
// chosen by name (STYLE.md principle 10; the names are mesh::boundaryName's). At a boundary node
// of a face whose normal direction has SBP weight H_n (= 1/2), the residual gets the SAT
//   R += (F*(q, qOther, n) - F_n(q)) / H_n,
// which replaces the SBP operator's boundary flux F_n(q) by F*: the SAT is conservative and
// vanishes when the boundary data is consistent with q (e.g. free stream at the farfield).
#include <string>

#include "flow/Euler.h"
#include "mesh/MultiBlock.h"

namespace aero::flow {

/// F* (5 values) at one boundary node. q: this side's state; qOther: the coincident node's state
/// on the other side of an interface (nullptr for the other kinds); n: the OUTWARD metric
/// vector (grad(xi_d)/J, signed to point out of the block); nhat: the boundary surface's unit
/// normal there (n / |n|, except at wall junctions: surfaceNormal in Residual.h; only the wall
/// and symmetry fluxes use it, and interface callers pass n itself); fs: free stream.
template <class T>
using BoundaryFluxFn = void (*)(const T* q, const T* qOther, const T* n, const T* nhat,
                                const FreeStream& fs, T* flux);

/// "farfield": characteristic upwind flux against the free stream, upwindFlux(q, q_inf, n):
/// incoming characteristics take the free-stream values, outgoing ones the interior's.
template <class T>
void farfieldFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                  T* flux);

/// "wall": inviscid slip wall as the upwind flux against the mirror state (normal velocity
/// reversed): the flux through n of the wall state (rho, u_t, p*), u_t = u - u_n nhat,
/// p* = p + rho u_n (u_n + c), u_n = u . nhat. With nhat = n / |n| only pressure crosses it,
/// F* = (0, p* n, 0): the SAT F* - F_n(q) penalizes the normal velocity U = u . n (mass and
/// energy rows -rho U, -rho H U), and the rho c u_n part makes it dissipative (the pressure-only
/// flux p* = p is not: its linearization has growing modes when flow crosses the wall, e.g. at an
/// impulsive start). At a wall junction n is one block's one-sided face vector, tilted by O(h)
/// from the wall, and the shared nhat makes F* - F_n(q) vanish for a flow along the true wall
/// (with nhat = n / |n| there, the junction's blocks would impose u . n = 0 for two different n
/// on the same interface-coupled state: a spurious stagnation point of O(1) truncation error).
template <class T>
void slipWallFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                  T* flux);

/// "symmetry": the plane Y = 0 as a mirror (the slip-wall flux); a free stream in the X-Z plane
/// satisfies it exactly.
template <class T>
void symmetryFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                  T* flux);

/// "interface": characteristic upwind flux between the two coincident nodes,
/// upwindFlux(q, qOther, n); F*(qa, qb, n) = -F*(qb, qa, -n), so the two sides' SATs telescope.
template <class T>
void interfaceFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                   T* flux);

/// The flux of a boundary condition by name: "farfield", "wall", "symmetry", "interface".
/// Throws CaseError naming `key` (e.g. the case-file key) for any other name.
template <class T>
BoundaryFluxFn<T> boundaryFlux(const std::string& name, const std::string& key = "boundary");
template <class T>
BoundaryFluxFn<T> boundaryFlux(mesh::BoundaryKind kind);
/// The flux of `kind` for the interior scheme: with InviscidScheme::EntropyConservative the
/// farfield and interface fluxes are entropyUpwindFlux (Euler.h); walls and symmetry planes are
/// the same for both (the slip-wall flux is entropy stable for u_n > -c).
template <class T>
BoundaryFluxFn<T> boundaryFlux(mesh::BoundaryKind kind, InviscidScheme scheme);

/// "farfield" and "interface" with the entropy-conservative flux as the central part.
template <class T>
void entropyFarfieldFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                         T* flux);
template <class T>
void entropyInterfaceFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                          T* flux);

}  // namespace aero::flow
