#pragma once
// Connectivity of a patch network: the unique control-point index (coincident control points
// merged) and the edge adjacency with its watertightness report.
#include <array>

#include "geometry/PatchSet.h"

namespace aero::geometry {

/// Unique control points. toUnique[offset(p) + i + countU*j] is the unique index of control
/// point (i, j) of patch p, where offset(p) is the sum of the control counts of patches < p.
struct ControlPointIndex {
    std::vector<int> toUnique;          // one per non-unique control point
    std::vector<int> patchOffset;       // size() + 1 entries
    std::vector<double> points;         // 3 * uniqueCount, the first representative's coords
    double tolerance = 0;
    int uniqueCount() const { return static_cast<int>(points.size() / 3); }
};

/// Merges control points closer than `tolerance` (absolute, world units). O(n log n).
ControlPointIndex buildControlPointIndex(const PatchSet& set, double tolerance = 1e-10);

/// One side of a shared edge: patch, edge (0: v=v0, 1: u=u1, 2: v=v1, 3: u=u0).
struct EdgeRef {
    int patch = -1;
    int edge = -1;
};

struct SharedEdge {
    EdgeRef a, b;
    bool reversed = false;   // b runs opposite to a
    double gap = 0;          // largest distance between the two boundary curves (sampled)
    bool identicalNets = false;  // the boundary control points coincide one to one
};

struct Adjacency {
    std::vector<SharedEdge> shared;
    std::vector<EdgeRef> free;   // edges with no partner (e.g. on a symmetry plane)
    double maxGap = 0;           // largest gap over shared edges
};

/// Pairs patch edges whose end points coincide within `tolerance` and whose midpoints are
/// within `matchDistance`; measures each pair's gap by sampling and projecting.
Adjacency buildAdjacency(const PatchSet& set, double tolerance = 1e-6);

/// Watertightness of a set with trimmed patches, where patch edges are not the body's edges.
/// The boundary pieces are the curves of the trim loops mapped onto their patches (and the four
/// edges of each untrimmed patch). A piece is matched when its midpoint lies within 1% of its
/// length (at least `tolerance`) of another patch's boundary; its gap is then the largest
/// distance from the piece to the other patches' boundaries (33 samples, the worst one refined;
/// parts farther than the 1 % are free boundary, see partlyFree).
/// Pieces split differently on the two sides are handled: the distance is to the boundaries of
/// all the other patches, so an edge along two patches on the other side (a T-junction) is
/// measured against both. Untrimmed sets use it too (`aeroform-cli info`) for the edges the
/// end-point pairing of buildAdjacency leaves free.
struct BoundaryGaps {
    int pieces = 0;     // non-degenerate boundary pieces
    int matched = 0;    // pieces along another patch's boundary
    int free = 0;       // pieces with no neighbour (e.g. on a symmetry plane)
    int partlyFree = 0;  // matched pieces with parts farther than 1 % of their length from every
                         // other boundary (an edge running on past the patches along it): those
                         // parts are free boundary, left out of the gap
    double maxGap = 0;  // largest gap over matched pieces
    int worstPatch = -1;                 // the patch of the piece with that gap (-1: none)
    std::array<double, 3> worstPoint{};  // ... and the point of the piece where it is
};
BoundaryGaps boundaryGaps(const PatchSet& set, double tolerance = 1e-6);

}  // namespace aero::geometry
