#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

// The symmetry plane is a slip wall for the Euler equations: the mirrored state has the same
// pressure and the opposite normal velocity, so only pressure crosses the plane.
template <class T>
void symmetryFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                  T* flux) {
    slipWallFlux(q, qOther, n, nhat, fs, flux);
}

template void symmetryFlux<double>(const double*, const double*, const double*, const double*,
                                   const FreeStream&, double*);
template void symmetryFlux<std::complex<double>>(const std::complex<double>*,
                                                 const std::complex<double>*,
                                                 const std::complex<double>*,
                                                 const std::complex<double>*, const FreeStream&,
                                                 std::complex<double>*);
template void symmetryFlux<MetricDual>(const MetricDual*,
                                                 const MetricDual*,
                                                 const MetricDual*,
                                                 const MetricDual*, const FreeStream&,
                                                 MetricDual*);
template void symmetryFlux<StateDual>(const StateDual*,
                                                 const StateDual*,
                                                 const StateDual*,
                                                 const StateDual*, const FreeStream&,
                                                 StateDual*);

}  // namespace aero::flow
