#pragma once
// The paper's sample geometry: the half y >= 0 of a sphere (symmetry plane Y = 0, X
// streamwise, Z up) as 20 bicubic B-spline patches with 6x6 control nets (720 control
// points), watertight: neighbouring patches share their edge control points exactly.
#include "geometry/PatchSet.h"

namespace aero::geometry {

struct HalfSphereOptions {
    double radius = 1.0;
    int controlPoints = 6;  // per direction and patch (>= degree + 1)
    int degree = 3;
};

PatchSet makeHalfSphere(const HalfSphereOptions& o = {});

/// Largest |  |S(u,v)| - r | over a dense sample of every patch (centre at the origin).
double maxRadialDeviation(const PatchSet& set, double radius, int samplesPerDirection = 41);

}  // namespace aero::geometry
