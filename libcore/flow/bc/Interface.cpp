#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

template <class T>
void interfaceFlux(const T* q, const T* qOther, const T* n, const T*, const FreeStream& fs,
                   T* flux) {
    upwindFlux(q, qOther, n, fs.gamma, flux);
}

template <class T>
void entropyInterfaceFlux(const T* q, const T* qOther, const T* n, const T*, const FreeStream& fs,
                          T* flux) {
    entropyUpwindFlux(q, qOther, n, fs.gamma, flux);
}

template void entropyInterfaceFlux<double>(const double*, const double*, const double*, const double*,
                                           const FreeStream&, double*);
template void entropyInterfaceFlux<std::complex<double>>(const std::complex<double>*,
                                                         const std::complex<double>*,
                                                         const std::complex<double>*,
                                                         const std::complex<double>*, const FreeStream&,
                                                         std::complex<double>*);
template void interfaceFlux<double>(const double*, const double*, const double*, const double*,
                                    const FreeStream&, double*);
template void interfaceFlux<std::complex<double>>(const std::complex<double>*,
                                                  const std::complex<double>*,
                                                  const std::complex<double>*,
                                                  const std::complex<double>*, const FreeStream&,
                                                  std::complex<double>*);
template void entropyInterfaceFlux<MetricDual>(const MetricDual*,
                                                         const MetricDual*,
                                                         const MetricDual*,
                                                         const MetricDual*, const FreeStream&,
                                                         MetricDual*);
template void interfaceFlux<MetricDual>(const MetricDual*,
                                                  const MetricDual*,
                                                  const MetricDual*,
                                                  const MetricDual*, const FreeStream&,
                                                  MetricDual*);
template void entropyInterfaceFlux<StateDual>(const StateDual*,
                                                         const StateDual*,
                                                         const StateDual*,
                                                         const StateDual*, const FreeStream&,
                                                         StateDual*);
template void interfaceFlux<StateDual>(const StateDual*,
                                                  const StateDual*,
                                                  const StateDual*,
                                                  const StateDual*, const FreeStream&,
                                                  StateDual*);

}  // namespace aero::flow
