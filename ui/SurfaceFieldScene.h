#pragma once
// A signed field on the drawn wall, e.g. the surface sensitivity of the objective after Flow >
// Compute Sensitivities: the wall's triangles (the patch scene's tessellation) coloured by a
// diverging scale (blue below zero, white at zero, red above) symmetric about zero, drawn just in
// front of the geometry's surfaces, with a colour bar whose title says what the field is.
// No VTK type is exposed here. GUI thread only; destroy while the viewport's context can be made
// current (see PatchScene).
#include <array>
#include <memory>
#include <string>
#include <vector>

class vtkRenderer;

namespace aero::ui {

class SurfaceFieldScene {
  public:
    explicit SurfaceFieldScene(vtkRenderer* renderer);
    ~SurfaceFieldScene();
    SurfaceFieldScene(const SurfaceFieldScene&) = delete;
    SurfaceFieldScene& operator=(const SurfaceFieldScene&) = delete;

    /// One triangulated piece of the wall: points (3 each), triangles (3 point indices each) and
    /// one value per point.
    struct Piece {
        std::vector<double> points;
        std::vector<int> triangles;
        std::vector<double> values;
    };
    /// Shows the pieces coloured over [-m, m], m the largest |value|; `title` for the colour bar.
    void setField(const std::vector<Piece>& pieces, const std::string& title);
    void clear();
    bool shown() const;
    int pointCount() const;
    /// The colour range [-m, m] (zeros when empty).
    std::array<double, 2> range() const;
    std::string title() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
