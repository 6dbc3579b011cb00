#include "geometry/PatchSet.h"

#include <algorithm>
#include <limits>

#include "common/Error.h"

namespace aero::geometry {

int PatchSet::controlPointCount() const {
    int n = 0;
    for (const Patch& p : patches) n += p.controlCount();
    return n;
}

std::string PatchSet::describe(int patch) const {
    std::string s = "patch " + std::to_string(patch + 1);
    if (patch < static_cast<int>(names.size()) && !names[patch].empty()) s += " ('" + names[patch] + "')";
    if (!source.empty()) s += " of '" + source + "'";
    return s;
}

void validate(const PatchSet& set) {
    if (set.patches.empty()) {
        throw GeometryError((set.source.empty() ? std::string("patch set") : "'" + set.source + "'") +
                            ": contains no patches");
    }
    if (!set.names.empty() && set.names.size() != set.patches.size()) {
        throw GeometryError("'" + set.source + "': " + std::to_string(set.names.size()) + " names for " +
                            std::to_string(set.patches.size()) + " patches");
    }
    for (int p = 0; p < set.size(); ++p) nurbs::validate(set.patches[p], set.describe(p));
}

namespace {

BoundingBox emptyBox() {
    constexpr double inf = std::numeric_limits<double>::infinity();
    return {{inf, inf, inf}, {-inf, -inf, -inf}};
}

void grow(BoundingBox& b, const std::vector<double>& xyz) {
    for (std::size_t a = 0; a < xyz.size(); a += 3) {
        for (int d = 0; d < 3; ++d) {
            b.min[d] = std::min(b.min[d], xyz[a + d]);
            b.max[d] = std::max(b.max[d], xyz[a + d]);
        }
    }
}

}  // namespace

BoundingBox controlBoundingBox(const PatchSet& set) {
    BoundingBox b = emptyBox();
    for (const Patch& p : set.patches) grow(b, p.points);
    return b;
}

BoundingBox surfaceBoundingBox(const PatchSet& set, int samples) {
    BoundingBox b = emptyBox();
    std::vector<double> us(samples), vs(samples), out(3 * static_cast<std::size_t>(samples) * samples);
    for (const Patch& p : set.patches) {
        for (int s = 0; s < samples; ++s) {
            const double t = static_cast<double>(s) / (samples - 1);
            us[s] = p.knotsU.front() + t * (p.knotsU.back() - p.knotsU.front());
            vs[s] = p.knotsV.front() + t * (p.knotsV.back() - p.knotsV.front());
        }
        nurbs::sampleGrid(p, us, vs, out.data());
        grow(b, out);
    }
    return b;
}

}  // namespace aero::geometry
