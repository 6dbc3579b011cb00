#pragma once
// Markers drawn over the geometry:
//   failed points      control points that could not be embedded in any lattice (magenta);
//   sensitivity arrows dS/dv of one design variable at surface points, like the red arrows of
//                      the paper's Figure 1 (arrow length proportional to |dS/dv|).
// No VTK type is exposed here. GUI thread only.
#include <array>
#include <memory>
#include <vector>

#include "geometry/PatchSet.h"

class vtkRenderer;

namespace aero::ui {

/// Surface points and dS/dv on a samples x samples grid per patch: `shape` gives the points,
/// `derivative` (the same layout, control points dA/dv; see Document::shapeDerivative) the
/// vectors. Outputs 3 values per point; patches listed in `hidden` (flags per patch, may be
/// empty) are skipped. Returns the largest |dS/dv|.
double sensitivityField(const geometry::PatchSet& shape, const geometry::PatchSet& derivative, int samples,
                        const std::vector<char>& hidden, std::vector<double>& points, std::vector<double>& vectors);

class OverlayScene {
  public:
    /// `arrowColour`: RGB in [0, 1] (red: the paper's dS/dv arrows).
    explicit OverlayScene(vtkRenderer* renderer, const std::array<double, 3>& arrowColour = {0.86, 0.08, 0.08});
    ~OverlayScene();
    OverlayScene(const OverlayScene&) = delete;
    OverlayScene& operator=(const OverlayScene&) = delete;

    /// 3 values per point.
    void setFailedPoints(const std::vector<double>& points);
    int failedPointCount() const;

    /// Arrows from `points` along `vectors` (3 values each), scaled so that the longest is
    /// `length` world units; vectors shorter than 1e-3 of the longest are left out.
    void setArrows(const std::vector<double>& points, const std::vector<double>& vectors, double length);
    void clearArrows();
    int arrowCount() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
