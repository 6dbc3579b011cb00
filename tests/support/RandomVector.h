#pragma once
// A deterministic random vector with entries uniform in [-1, 1), for directions and right-hand
// sides in tests.
#include <random>
#include <vector>

namespace aero::test {

inline std::vector<double> randomVector(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

}  // namespace aero::test
