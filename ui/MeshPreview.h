#pragma once
// The mesh preview's work, as it runs on the worker thread (no Qt, no VTK, no Document): the
// shape and mesh stages of study::CaseEvaluator, the same code `aeroform-cli mesh` runs, on a
// copy of the document's case:
//   lattices -> deformed wall -> extrudeToFarfield(baseline) -> moveControlGrid -> regenerateAll
//   -> cellQuality, summarize.
// The GUI thread fills a MeshPreviewInput from the document, runs runMeshPreview() through a
// job of the JobRunner and hands the result (shared, read-only from then on) to the scene and panel.
// Also here: the quality metrics by name and their colour scale, shared by the 3D view
// (MeshScene) and the histogram (MeshPanel) so that both show the same colours.
#include <array>
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "geometry/PatchSet.h"
#include "io/CaseFile.h"
#include "mesh/Elasticity.h"
#include "mesh/MultiBlock.h"
#include "mesh/Quality.h"
#include "mesh/StructuredGrid.h"

namespace aero::ui {

// ---- Quality metrics ----------------------------------------------------------------------------

enum class QualityMetric { ScaledJacobian = 0, MinJacobian, Orthogonality, AspectRatio, Skewness };
inline constexpr int kQualityMetrics = 5;

/// "Scaled Jacobian", ... (for people).
const char* metricLabel(QualityMetric m);
/// "scaled_jacobian", ... (the cell-field names of the exported .vtm, as `aeroform-cli mesh`).
const char* metricField(QualityMetric m);
/// True where a larger value is a better cell (Jacobians, orthogonality).
bool higherIsBetter(QualityMetric m);
/// Per-cell values of one block for metric m.
const std::vector<double>& metricValues(const mesh::CellQuality& q, QualityMetric m);
const mesh::MetricSummary& metricSummary(const mesh::QualitySummary& s, QualityMetric m);

/// The colour scale: t = 0 is the bad end (red), through orange and pale yellow to the good
/// end at 1 (a light grey-blue, close to the geometry's colour): a healthy grid looks calm and
/// poor cells stand out. RGB in [0, 1].
std::array<double, 3> qualityColour(double t);
/// The range a metric is coloured (and binned) over: the data's finite min and max (widened a
/// little when they coincide).
std::array<double, 2> colourRange(const mesh::QualitySummary& s, QualityMetric m);
/// Position of `value` on the colour scale of metric m over the data range [lo, hi]: 0 bad,
/// 1 good. A log scale is used where `logScale`.
double qualityPosition(QualityMetric m, double value, double lo, double hi, bool logScale);
/// Whether metric m is coloured on a log scale for data in [lo, hi]: aspect ratios spanning
/// more than a decade, cell volumes (min. Jacobian) spanning more than two.
bool useLogScale(QualityMetric m, double lo, double hi);
/// Cells per bin of metric m over the colour range [lo, hi] (log-spaced bins where logScale),
/// all blocks; values outside go to the end bins, non-finite values are left out. Unlike
/// MetricSummary::histogram (fixed ranges such as [-1, 1]), this resolves the cells at hand.
std::vector<long> rangeHistogram(const std::vector<mesh::CellQuality>& q, QualityMetric m,
                                 double lo, double hi, bool logScale, int bins);

// ---- The work ---------------------------------------------------------------------------------

struct MeshPreviewInput {
    geometry::PatchSet baseline;  // the mesh is generated around the baseline ...
    io::CaseFile caseFile;        // ... with the case's level, options, lattices and design
    std::vector<double> wall;     // the document's wall when the preview started (unique control
                                  // points, 3 each): what the result is compared with later
    int worstCells = 25;          // how many of the worst cells to locate
};

enum class MeshPreviewStatus {
    Done,          // grid ready (moved if needed)
    NotConverged,  // the elasticity move stopped early; the grid is the last increment's
    Cancelled      // stopped at the cancellation flag; nothing else is filled in
};

struct MeshPreviewResult {
    MeshPreviewStatus status = MeshPreviewStatus::Done;
    std::string level;
    mesh::MultiBlockMesh mesh;                // control grid b (moved) and blocks
    std::vector<mesh::StructuredGrid> grids;  // regenerated grid, one per block
    std::vector<mesh::CellQuality> quality;   // per block
    mesh::QualitySummary summary;             // over all blocks; worst cells by scaled Jacobian
    mesh::WallBend wallBend;                  // the wall's sharpest node-to-node turn
    bool moved = false;                       // the wall differed from the baseline's
    mesh::MoveReport move;                    // when moved
    std::vector<double> wall;                 // the input's wall (what the grid was made for)
    double seconds = 0;                       // wall-clock time of the whole run
    std::string message;                      // why it stopped early (NotConverged)

    long gridNodes() const { return mesh.gridNodeCount(); }
};

/// fraction in [0, 1], text for the status bar. Called on the worker thread.
using MeshPreviewProgress = std::function<void(double fraction, const std::string& text)>;

/// Runs the pipeline. The wall is not moved when `in.wall` matches the generated wall to
/// round-off (1e-12 of the body size), e.g. a lattice at its baseline: the grid is then exact.
/// `cancel` is polled between stages and between elasticity increments. Throws aero::Error
/// (GeometryError for a body that cannot be meshed, naming the patch) like the CLI.
MeshPreviewResult runMeshPreview(const MeshPreviewInput& in,
                                 const MeshPreviewProgress& progress = {},
                                 const std::atomic<bool>* cancel = nullptr);

/// Writes the grid by extension: .vtm (VTK multiblock: group "grid" with the five quality
/// metrics as cell fields, group "control_grid" with the control net b; one .vts per block in
/// a folder named after the file), .xyz (binary Plot3D) or .p3d/.fmt (ASCII Plot3D). Throws
/// InputError for another extension or a file that cannot be written.
void writeGrid(const MeshPreviewResult& r, const std::string& path);

}  // namespace aero::ui
