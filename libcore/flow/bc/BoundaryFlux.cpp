#include "flow/bc/BoundaryFlux.h"

#include <complex>

#include "common/Error.h"

namespace aero::flow {

template <class T>
BoundaryFluxFn<T> boundaryFlux(const std::string& name, const std::string& key) {
    if (name == "farfield") return &farfieldFlux<T>;
    if (name == "wall") return &slipWallFlux<T>;
    if (name == "symmetry") return &symmetryFlux<T>;
    if (name == "interface") return &interfaceFlux<T>;
    throw CaseError(key + ": unknown boundary condition '" + name +
                    "' (expected farfield, wall, symmetry or interface)");
}

template <class T>
BoundaryFluxFn<T> boundaryFlux(mesh::BoundaryKind kind) {
    return boundaryFlux<T>(mesh::boundaryName(kind));
}

template <class T>
BoundaryFluxFn<T> boundaryFlux(mesh::BoundaryKind kind, InviscidScheme scheme) {
    if (scheme == InviscidScheme::EntropyConservative) {
        if (kind == mesh::BoundaryKind::Farfield) return &entropyFarfieldFlux<T>;
        if (kind == mesh::BoundaryKind::Interface) return &entropyInterfaceFlux<T>;
    }
    return boundaryFlux<T>(kind);
}

#define AERO_INSTANTIATE(T)                                                                        \
    template BoundaryFluxFn<T> boundaryFlux<T>(mesh::BoundaryKind, InviscidScheme);                \
    template BoundaryFluxFn<T> boundaryFlux<T>(const std::string&, const std::string&);            \
    template BoundaryFluxFn<T> boundaryFlux<T>(mesh::BoundaryKind);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
