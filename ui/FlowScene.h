#pragma once
// The VTK representation of a flow solution (FlowRunResult), added to one renderer:
//   wall            the grid's wall faces, coloured by the chosen field (entropy s - s_inf as the
//                   paper's Figure 6, Cp, Mach, pressure) interpolated between the nodes;
//   symmetry plane  the grid's faces on Y = 0, likewise;
//   slice           a plane x, y or z = const cut through every block (off at first);
//   contour lines   iso-lines of the field on the parts shown (optional);
//   section lines   the spanwise cuts of the wall the section view plots, drawn on the body;
// with a colour bar naming the field over its range: the field's range on the wall and the
// symmetry plane (the entropy's 1st to 99th percentile), or a range the user chose.
//
// The scene keeps the result it shows (shared, read-only). It also cuts the wall at spanwise
// stations for the section view (vtkCutter: visualization, no numerics of our own). No VTK type
// is exposed here. GUI thread only; the scene does not render by itself (ask the viewport).
// Destroy it while the viewport's context can be made current (see PatchScene).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "FlowRun.h"

class vtkRenderer;

namespace aero::ui {

enum class FlowPart { Wall = 0, Symmetry, Slice, Contours, Sections };
inline constexpr int kFlowParts = 5;

/// One spanwise cut of the wall at y = station: polylines of (x, z, value of the field).
struct SectionCut {
    double station = 0;
    std::vector<std::vector<std::array<double, 3>>> pieces;
    /// Chord-wise extent (min and max x); zeros when the cut is empty.
    std::array<double, 2> xRange() const;
};

class FlowScene {
  public:
    explicit FlowScene(vtkRenderer* renderer);
    ~FlowScene();
    FlowScene(const FlowScene&) = delete;
    FlowScene& operator=(const FlowScene&) = delete;

    /// Shows `result` (null: clear). Keeps the field, range choice, parts, slice and stations.
    void setResult(std::shared_ptr<const FlowRunResult> result);
    void clear() { setResult(nullptr); }
    bool empty() const;
    const FlowRunResult* result() const;

    void setField(FlowField field);
    FlowField field() const;
    /// A fixed colour range; unset: the field's range on the wall and the symmetry plane (for
    /// the entropy its 1st to 99th percentile there: a few nodes would wash out the rest).
    void setRange(std::optional<std::pair<double, double>> range);
    /// The range the colours (and the colour bar) span now.
    std::pair<double, double> range() const;
    /// The automatic range of `field` for the current result ({0, 1} when empty).
    std::pair<double, double> autoRange(FlowField field) const;
    /// The colour bar's title (the field's name).
    std::string barTitle() const;

    /// Iso-lines of the field: `count` levels evenly inside the colour range.
    void setContourCount(int count);
    int contourCount() const;

    void setPartVisible(FlowPart part, bool visible);
    bool partVisible(FlowPart part) const;
    /// Whether the wall of the solution is drawn (the geometry's surfaces make way for it).
    bool wallShown() const;
    /// Draws nothing while false (the parts keep their switches): e.g. while the optimization's
    /// evaluations take the view.
    void setShown(bool shown);
    bool shown() const;
    /// The colour bar (on by default; a second scene beside the first shares its bar).
    void setColourBarShown(bool shown);
    /// Draws everything moved by `offset` (a copy beside another: the data stays where it is).
    void setOffset(const std::array<double, 3>& offset);

    /// The slice: the plane x (axis 0), y (1) or z (2) = position.
    void setSlice(int axis, double position);
    int sliceAxis() const;
    double slicePosition() const;

    /// Cuts the wall at y = station for every station: the field's values along the cuts are
    /// those of `field`. Also draws the cuts in 3D (part Sections).
    std::vector<SectionCut> cutWall(const std::vector<double>& stations, FlowField field);

    /// Axis-aligned bounds {xmin, xmax, ymin, ymax, zmin, zmax}: of the wall, of the whole grid.
    std::array<double, 6> wallBounds() const;
    std::array<double, 6> gridBounds() const;
    /// Cells currently drawn by the slice (0 when off or empty); for tests.
    long sliceCells() const;
    /// Line segments of the contour lines on the visible parts; for tests.
    long contourSegments() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
