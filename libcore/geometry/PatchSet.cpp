#include "geometry/PatchSet.h"

#include <algorithm>
#include <limits>

#include "common/Error.h"
#include "geometry/Units.h"

namespace aero::geometry {

int PatchSet::trimmedCount() const {
    int n = 0;
    for (int p = 0; p < size(); ++p) n += trimmed(p) ? 1 : 0;
    return n;
}

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
    if (!set.trims.empty() && set.trims.size() != set.patches.size()) {
        throw GeometryError("'" + set.source + "': " + std::to_string(set.trims.size()) + " trims for " +
                            std::to_string(set.patches.size()) + " patches");
    }
    if (!set.unit.empty() && !findLengthUnit(set.unit)) {
        throw GeometryError("'" + set.source + "': unknown length unit '" + set.unit + "' (known: " + knownLengthUnits() + ")");
    }
    for (int p = 0; p < set.size(); ++p) {
        nurbs::validate(set.patches[p], set.describe(p));
        if (set.trimmed(p)) validate(set.trims[p], set.patches[p], set.describe(p));
    }
}

void requireUntrimmed(const PatchSet& set, std::string_view what) {
    const int count = set.trimmedCount();
    if (count == 0) return;
    int first = 0;
    while (!set.trimmed(first)) ++first;
    std::string m = std::string(what) + " needs untrimmed patches: " + set.describe(first) + " is trimmed";
    if (count > 1) m += " (" + std::to_string(count - 1) + " more trimmed patch" + (count > 2 ? "es" : "") + ")";
    throw GeometryError(m);
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
    for (int k = 0; k < set.size(); ++k) {
        const Patch& p = set.patches[k];
        for (int s = 0; s < samples; ++s) {
            const double t = static_cast<double>(s) / (samples - 1);
            us[s] = p.knotsU.front() + t * (p.knotsU.back() - p.knotsU.front());
            vs[s] = p.knotsV.front() + t * (p.knotsV.back() - p.knotsV.front());
        }
        nurbs::sampleGrid(p, us, vs, out.data());
        if (!set.trimmed(k)) {
            grow(b, out);
            continue;
        }
        // Trimmed: the grid points inside the trim, then points along the loops themselves.
        const TrimPolygons poly = polygonize(set.trims[k], p, 8);
        std::vector<double> kept;
        for (int j = 0; j < samples; ++j)
            for (int i = 0; i < samples; ++i)
                if (contains(poly, us[i], vs[j])) kept.insert(kept.end(), &out[3 * (i + samples * j)], &out[3 * (i + samples * j)] + 3);
        for (const auto& loop : poly.loops)
            for (const Point2& uv : loop) {
                const auto x = nurbs::evaluate(p, uv[0], uv[1]);
                kept.insert(kept.end(), {x.x(), x.y(), x.z()});
            }
        grow(b, kept);
    }
    return b;
}

}  // namespace aero::geometry
