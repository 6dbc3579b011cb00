#pragma once
// A network of NURBS patches: the geometry A of the paper (its control points are what the
// first FFD level embeds).
#include <array>
#include <string>
#include <vector>

#include "nurbs/Surface.h"

namespace aero::geometry {

using Patch = nurbs::Surface<double>;

struct PatchSet {
    std::vector<Patch> patches;
    std::vector<std::string> names;  // one per patch (may be empty strings)
    std::string source;              // where it came from (file path or generator), for messages

    int size() const { return static_cast<int>(patches.size()); }
    /// Total number of (non-unique) control points over all patches.
    int controlPointCount() const;
    /// "patch 3 ('wing_upper') of 'file.igs'": how every message names a patch.
    std::string describe(int patch) const;
};

/// Validates every patch (knots, sizes, weights, finite coordinates); throws GeometryError
/// naming the source and the patch. Also rejects an empty set.
void validate(const PatchSet& set);

struct BoundingBox {
    std::array<double, 3> min{0, 0, 0}, max{0, 0, 0};
};

/// Bounding box of the control points (which contains every surface point: convex hull).
BoundingBox controlBoundingBox(const PatchSet& set);

/// Bounding box of the surfaces themselves, from a samples x samples grid on every patch.
BoundingBox surfaceBoundingBox(const PatchSet& set, int samples = 33);

}  // namespace aero::geometry
