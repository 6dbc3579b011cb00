#pragma once
// The VTK representation of a patch set: three actors added to one renderer,
//   surfaces       every patch sampled on a structured grid, smooth-shaded with analytic
//                  normals (Su x Sv), each patch oriented away from the set's centre; a
//                  trimmed patch only inside its trim loops (the grid clipped in parameter
//                  space, twice as fine);
//   patch edges    the four boundary curves of every patch (its trim loops when trimmed), dark lines;
//   control nets   control points and the lines of each net (hidden by default).
// No VTK type is exposed here beyond the renderer it draws into.
//
// Deformations keep a patch set's layout (patch count, control-net sizes, trims): updatePatches()
// then re-samples only the given patches and overwrites their points in place (no new VTK
// pipeline, no new cells), which is what keeps dragging interactive. Trims live in parameter
// space, so a trimmed patch's tessellation survives any deformation: only its points move.
//
// GUI thread only. The scene does not render by itself: after changing it, ask the viewport
// for a render. Removing actors releases their GL resources, so destroy the scene while its
// viewport's context can be made current (see MainWindow).
#include <array>
#include <memory>
#include <vector>

#include "geometry/PatchSet.h"

class vtkCamera;
class vtkRenderer;

namespace aero::ui {

struct PatchSceneOptions {
    int surfaceSamples = 33;  // grid points per direction and patch (>= 2)
    int edgeSamples = 65;     // points per boundary curve (>= 2)
    bool tintPatches = true;  // vary the lightness of neighbouring patches slightly
};

class PatchScene {
  public:
    /// Adds the (empty) actors to `renderer`, which must outlive the scene.
    explicit PatchScene(vtkRenderer* renderer, PatchSceneOptions options = {});
    ~PatchScene();  // removes the actors from the renderer
    PatchScene(const PatchScene&) = delete;
    PatchScene& operator=(const PatchScene&) = delete;

    /// Replaces the displayed geometry with `set` (copied into VTK arrays; the set is not kept).
    /// Throws GeometryError (libcore) if the set is invalid; the scene is unchanged then.
    void setPatchSet(const geometry::PatchSet& set);
    /// Re-samples the listed patches of `set` in place (surfaces, edges, control nets). `set`
    /// must have the layout of the displayed set (else the whole scene is rebuilt with
    /// setPatchSet). Each patch keeps the orientation chosen by setPatchSet.
    void updatePatches(const geometry::PatchSet& set, const std::vector<int>& patches);
    /// Shows nothing.
    void clear();

    /// Per-patch visibility (all visible after setPatchSet).
    void setPatchVisible(int patch, bool visible);
    bool patchVisible(int patch) const;
    /// Tints these patches as selected (others normal).
    void setHighlightedPatches(const std::vector<int>& patches);

    void setSurfacesVisible(bool visible);
    void setEdgesVisible(bool visible);
    void setControlNetsVisible(bool visible);
    bool surfacesVisible() const;
    bool edgesVisible() const;
    bool controlNetsVisible() const;

    int patchCount() const;
    int controlPointCount() const;  // non-unique, as geometry::PatchSet::controlPointCount()

    /// What is drawn for one patch (for tests and inspection): surface points (3 per point) with
    /// their parameters (2 per point), triangles (3 point indices each, counter-clockwise in
    /// (u, v)), and the edge polylines (3 per point). Empty for an invalid index.
    struct SurfaceMesh {
        std::vector<double> points, uv;
        std::vector<int> triangles;
        std::vector<std::vector<double>> edges;
    };
    SurfaceMesh surfaceMesh(int patch) const;
    bool empty() const { return patchCount() == 0; }

    /// Axis-aligned bounds {xmin, xmax, ymin, ymax, zmin, zmax} of the sampled surfaces and
    /// control nets; all zero when empty.
    std::array<double, 6> bounds() const;

    /// Points `camera` along `viewDirection` (from the camera towards the scene) with
    /// `viewUp`, centred on what is visible on screen, at the distance where the projected
    /// surfaces (and control nets, if shown) fill the share `fill` of the smaller side of a
    /// viewport of width/height `aspect`. Keeps the camera's view angle. No-op when empty.
    /// `extra` (3 per point, may be null) are further points to keep in view, e.g. lattices.
    void fitCamera(vtkCamera* camera, double aspect, const std::array<double, 3>& viewDirection,
                   const std::array<double, 3>& viewUp, double fill = 0.8,
                   const std::vector<double>* extra = nullptr) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
