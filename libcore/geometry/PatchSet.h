#pragma once
// A network of NURBS patches: the geometry A of the paper (its control points are what the
// first FFD level embeds).
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/Trim.h"
#include "nurbs/Surface.h"

namespace aero::geometry {

using Patch = nurbs::Surface<double>;

struct PatchSet {
    std::vector<Patch> patches;
    std::vector<std::string> names;  // one per patch (may be empty strings)
    std::string source;              // where it came from (file path or generator), for messages
    /// Trimming per patch: empty when no patch is trimmed, else one entry per patch (an entry
    /// whose trimmed() is false leaves its patch whole). See geometry/Trim.h.
    std::vector<PatchTrim> trims;
    /// Length unit of the coordinates as the file states it: a canonical name of
    /// geometry/Units.h ("mm", "m", "in", ...), or "" when the source states none.
    std::string unit;

    int size() const { return static_cast<int>(patches.size()); }
    /// Whether patch p is trimmed.
    bool trimmed(int p) const { return p < static_cast<int>(trims.size()) && trims[p].trimmed(); }
    /// Number of trimmed patches.
    int trimmedCount() const;
    /// Total number of (non-unique) control points over all patches.
    int controlPointCount() const;
    /// "patch 3 ('wing_upper') of 'file.igs'": how every message names a patch.
    std::string describe(int patch) const;
};

/// Validates every patch (knots, sizes, weights, finite coordinates), its trim (geometry/Trim.h)
/// and the unit (known or empty); throws GeometryError naming the source and the patch. Also
/// rejects an empty set.
void validate(const PatchSet& set);

/// Throws GeometryError if any patch is trimmed: "<what> needs untrimmed patches: patch 3 ('x') of
/// 'f.igs' is trimmed (2 more trimmed patches)". For the layers that work on whole patches.
void requireUntrimmed(const PatchSet& set, std::string_view what);

struct BoundingBox {
    std::array<double, 3> min{0, 0, 0}, max{0, 0, 0};
};

/// Bounding box of the control points (which contains every surface point: convex hull).
BoundingBox controlBoundingBox(const PatchSet& set);

/// Bounding box of the surfaces themselves, from a samples x samples grid on every patch (of a
/// trimmed patch: the grid points inside its trim and points along its trim loops).
BoundingBox surfaceBoundingBox(const PatchSet& set, int samples = 33);

}  // namespace aero::geometry
