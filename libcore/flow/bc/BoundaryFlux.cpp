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

template BoundaryFluxFn<double> boundaryFlux<double>(const std::string&, const std::string&);
template BoundaryFluxFn<std::complex<double>> boundaryFlux<std::complex<double>>(
    const std::string&, const std::string&);
template BoundaryFluxFn<double> boundaryFlux<double>(mesh::BoundaryKind);
template BoundaryFluxFn<std::complex<double>> boundaryFlux<std::complex<double>>(mesh::BoundaryKind);

}  // namespace aero::flow
