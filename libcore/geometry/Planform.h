#pragma once
// The planform of a shape: its span along Y and its shadow on the plane Z = 0 (seen from above),
// the figures the paper reports for its optimized body (Section V: half-span 2.8990, projected
// area 3.9299, aspect ratio 4.3). A shape that lies on one side of the symmetry plane Y = 0 is
// half of a body mirrored there, as in the paper: its half-span is its largest |y|, its projected
// area the half-body's shadow, and the aspect ratio that of the whole body, (2 s)^2 / (2 S). A
// shape that crosses Y = 0 is a whole body: half-span = (max y - min y) / 2, and the aspect
// ratio span^2 / S.
//
// How: every patch is sampled on a parameter grid that refines each knot span (64 intervals per
// direction, fewer when thousands of patches would exceed about 2 million samples); the shadow,
// the union of the sampled quadrilaterals' projections, is rasterized on 1,024 cells along its
// longer side (cell centres counted once however many quadrilaterals cover them); the largest y
// is refined by zooming in on the best sample (the lowest y of a whole body is not). The
// half-sphere's half-disk comes out within 4e-5 of pi/2, in 30-50 ms, and its half-span is 1 to
// the patches' own accuracy (2e-5).
#include "geometry/PatchSet.h"

namespace aero::geometry {

struct Planform {
    double halfSpan = 0;       // largest |y| of a half body; half the Y extent of a whole one
    double projectedArea = 0;  // area of the shadow on Z = 0 (of the shape as given)
    double aspectRatio = 0;    // of the whole body: (2 s)^2 / (2 S) for a half body
    bool halfBody = true;      // the shape lies in y >= 0 (to round-off of its size)
};

/// Throws GeometryError naming the patch when a patch is trimmed (the whole patch would be
/// counted; as for enclosedVolume).
Planform planform(const PatchSet& set);

}  // namespace aero::geometry
