#pragma once
// Shared checks used by the validate() functions of curves, surfaces and volumes.
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "common/Error.h"

namespace aero::nurbs::detail {

inline void checkPointsAndWeights(const std::vector<double>& points, const std::vector<double>& weights,
                                  std::size_t count, std::string_view what) {
    if (points.size() != 3 * count) {
        throw GeometryError(std::string(what) + ": has " + std::to_string(points.size()) +
                            " coordinates, expected " + std::to_string(3 * count));
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!std::isfinite(points[i])) {
            throw GeometryError(std::string(what) + ": control point " + std::to_string(i / 3) +
                                " has a non-finite coordinate");
        }
    }
    if (!weights.empty()) {
        if (weights.size() != count) {
            throw GeometryError(std::string(what) + ": has " + std::to_string(weights.size()) +
                                " weights, expected " + std::to_string(count));
        }
        for (std::size_t i = 0; i < weights.size(); ++i) {
            if (!std::isfinite(weights[i]) || !(weights[i] > 0.0)) {
                throw GeometryError(std::string(what) + ": weight " + std::to_string(i) +
                                    " is not a positive finite number");
            }
        }
    }
}

}  // namespace aero::nurbs::detail
