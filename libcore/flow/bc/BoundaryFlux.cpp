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

template BoundaryFluxFn<double> boundaryFlux<double>(mesh::BoundaryKind, InviscidScheme);
template BoundaryFluxFn<std::complex<double>> boundaryFlux<std::complex<double>>(mesh::BoundaryKind,
                                                                               InviscidScheme);
template BoundaryFluxFn<double> boundaryFlux<double>(const std::string&, const std::string&);
template BoundaryFluxFn<std::complex<double>> boundaryFlux<std::complex<double>>(
    const std::string&, const std::string&);
template BoundaryFluxFn<double> boundaryFlux<double>(mesh::BoundaryKind);
template BoundaryFluxFn<std::complex<double>> boundaryFlux<std::complex<double>>(mesh::BoundaryKind);
template BoundaryFluxFn<MetricDual> boundaryFlux<MetricDual>(mesh::BoundaryKind,
                                                                               InviscidScheme);
template BoundaryFluxFn<MetricDual> boundaryFlux<MetricDual>(
    const std::string&, const std::string&);
template BoundaryFluxFn<MetricDual> boundaryFlux<MetricDual>(mesh::BoundaryKind);
template BoundaryFluxFn<StateDual> boundaryFlux<StateDual>(mesh::BoundaryKind,
                                                                               InviscidScheme);
template BoundaryFluxFn<StateDual> boundaryFlux<StateDual>(
    const std::string&, const std::string&);
template BoundaryFluxFn<StateDual> boundaryFlux<StateDual>(mesh::BoundaryKind);

}  // namespace aero::flow
