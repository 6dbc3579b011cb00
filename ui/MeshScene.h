#pragma once
// The VTK representation of a mesh preview (MeshPreviewResult), four parts added to one
// renderer, each toggled on its own:
//   control grid    the control net b of every block as a dark violet wireframe (off at first);
//   wall            the grid's wall faces, one quad per grid face, coloured by the chosen metric
//                   of the cell on it, with the grid lines drawn;
//   symmetry plane  the grid's faces on Y = 0, likewise;
//   slice           one constant-k layer of cells across all blocks (k = 0 at the wall), drawn
//                   on its k-face and coloured by those cells (off at first).
// A colour bar names the metric. Cells can be marked: bad cells (non-positive Jacobian) in red,
// and one focused cell (e.g. the worst-cells row the user clicked) in yellow, each as its 12
// edges plus a dot at its centroid; marks are drawn on top of everything (a second renderer
// layer sharing the camera) so that a bad cell is never hidden behind the body.
//
// The scene keeps the result it shows (shared, read-only). No VTK type is exposed here. GUI
// thread only; the scene does not render by itself (ask the viewport). Destroy it while the
// viewport's context can be made current (see PatchScene).
#include <array>
#include <memory>
#include <vector>

#include "MeshPreview.h"

class vtkRenderer;

namespace aero::ui {

enum class MeshPart { ControlGrid = 0, Wall, Symmetry, Slice };
inline constexpr int kMeshParts = 4;

/// One grid cell: block index and cell (i, j, k) of that block.
struct GridCell {
    int block = -1;
    std::array<int, 3> cell{0, 0, 0};
    bool operator==(const GridCell&) const = default;
};

class MeshScene {
  public:
    /// Adds the (empty) actors to `renderer`, which must outlive the scene and belong to a
    /// render window already (the marks go into a renderer of the same window, layer 1).
    explicit MeshScene(vtkRenderer* renderer);
    ~MeshScene();
    MeshScene(const MeshScene&) = delete;
    MeshScene& operator=(const MeshScene&) = delete;

    /// Shows `result` (null: clear). Keeps the part visibilities, the metric and the slice
    /// (clamped); drops the marks.
    void setResult(std::shared_ptr<const MeshPreviewResult> result);
    void clear() { setResult(nullptr); }
    bool empty() const;
    const MeshPreviewResult* result() const;

    /// Colours wall, symmetry plane and slice by `metric` over the data's range.
    void setMetric(QualityMetric metric);
    QualityMetric metric() const;

    /// The slice's cell layer k (clamped to the blocks' layers).
    void setSlice(int layer);
    int slice() const;
    /// Number of cell layers along k (the largest over the blocks); 0 when empty.
    int sliceLayers() const;

    void setPartVisible(MeshPart part, bool visible);
    bool partVisible(MeshPart part) const;
    /// Whether anything of the grid is drawn (a part visible and a result shown).
    bool anythingVisible() const;

    /// Cells drawn in red (replaces the previous set).
    void setMarkedCells(const std::vector<GridCell>& cells);
    int markedCellCount() const;
    /// The cell drawn in yellow; block < 0: none.
    void setFocusCell(const GridCell& cell);
    GridCell focusCell() const;

    /// Mean of the cell's 8 corners and the largest distance between two of them (its size);
    /// false for a cell that does not exist.
    bool cellCentre(const GridCell& cell, std::array<double, 3>& centre, double& size) const;
    /// Axis-aligned bounds {xmin, xmax, ymin, ymax, zmin, zmax} of the wall; zeros when empty.
    std::array<double, 6> wallBounds() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
