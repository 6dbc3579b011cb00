#include "MeshScene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace aero::ui {

namespace {

constexpr int kColours = 256;  // entries of the lookup table
constexpr int kMarkLayer = 1;  // renderer layer of the cell marks (over the scene)

// Quads of one grid plane and the metrics of the cells they colour, gathered block by block.
class SurfaceBuilder {
  public:
    SurfaceBuilder() {
        points_->SetDataTypeToDouble();
        for (int m = 0; m < kQualityMetrics; ++m) {
            fields_[static_cast<std::size_t>(m)] = vtkSmartPointer<vtkDoubleArray>::New();
            fields_[static_cast<std::size_t>(m)]->SetName(
                metricField(static_cast<QualityMetric>(m)));
        }
    }

    // The node plane index[d] == plane of grid g, one quad per face, coloured by the cells with
    // index[d] == layer.
    void addPlane(const mesh::StructuredGrid& g, const mesh::CellQuality& q, int d, int plane,
                  int layer) {
        const int a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
        const int na = g.dims[static_cast<std::size_t>(a)],
                  nb = g.dims[static_cast<std::size_t>(b)];
        if (g.dims[static_cast<std::size_t>(d)] < 2 || na < 2 || nb < 2) return;
        const vtkIdType base = points_->GetNumberOfPoints();
        std::array<int, 3> n{};
        n[static_cast<std::size_t>(d)] = plane;
        for (int jb = 0; jb < nb; ++jb)
            for (int ia = 0; ia < na; ++ia) {
                n[static_cast<std::size_t>(a)] = ia;
                n[static_cast<std::size_t>(b)] = jb;
                points_->InsertNextPoint(g.at(n[0], n[1], n[2]));
            }
        std::array<int, 3> c{};
        c[static_cast<std::size_t>(d)] = layer;
        for (int jb = 0; jb + 1 < nb; ++jb)
            for (int ia = 0; ia + 1 < na; ++ia) {
                const vtkIdType p = base + ia + static_cast<vtkIdType>(na) * jb;
                const vtkIdType ids[4] = {p, p + 1, p + 1 + na, p + na};
                quads_->InsertNextCell(4, ids);
                c[static_cast<std::size_t>(a)] = ia;
                c[static_cast<std::size_t>(b)] = jb;
                const long cell = g.cell(c[0], c[1], c[2]);
                for (int m = 0; m < kQualityMetrics; ++m)
                    fields_[static_cast<std::size_t>(m)]->InsertNextValue(metricValues(
                        q, static_cast<QualityMetric>(m))[static_cast<std::size_t>(cell)]);
            }
    }

    vtkSmartPointer<vtkPolyData> build() {
        auto poly = vtkSmartPointer<vtkPolyData>::New();
        poly->SetPoints(points_);
        poly->SetPolys(quads_);
        for (auto& f : fields_) poly->GetCellData()->AddArray(f);
        return poly;
    }

  private:
    vtkNew<vtkPoints> points_;
    vtkNew<vtkCellArray> quads_;
    std::array<vtkSmartPointer<vtkDoubleArray>, kQualityMetrics> fields_;
};

// The 12 edges of cell c of grid g as lines, and its centroid as a vertex.
void addCellMark(const mesh::StructuredGrid& g, const std::array<int, 3>& c, vtkPoints* points,
                 vtkCellArray* verts, vtkCellArray* lines) {
    const vtkIdType base = points->GetNumberOfPoints();
    double centre[3] = {0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        const double* x =
            g.at(c[0] + (corner & 1), c[1] + ((corner >> 1) & 1), c[2] + ((corner >> 2) & 1));
        points->InsertNextPoint(x);
        for (int k = 0; k < 3; ++k) centre[k] += x[k] / 8;
    }
    const vtkIdType mid = points->InsertNextPoint(centre);
    verts->InsertNextCell(1, &mid);
    // Corner bits: 1 = +i, 2 = +j, 4 = +k; an edge joins corners that differ in one bit.
    for (int corner = 0; corner < 8; ++corner)
        for (int bit : {1, 2, 4})
            if (!(corner & bit)) {
                const vtkIdType ids[2] = {base + corner, base + (corner | bit)};
                lines->InsertNextCell(2, ids);
            }
}

bool validCell(const MeshPreviewResult* r, const GridCell& c) {
    if (!r || c.block < 0 || c.block >= static_cast<int>(r->grids.size())) return false;
    const auto& g = r->grids[static_cast<std::size_t>(c.block)];
    for (int d = 0; d < 3; ++d)
        if (c.cell[static_cast<std::size_t>(d)] < 0 ||
            c.cell[static_cast<std::size_t>(d)] + 1 >= g.dims[static_cast<std::size_t>(d)])
            return false;
    return true;
}

}  // namespace

struct MeshScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    vtkNew<vtkRenderer> marks;  // layer kMarkLayer, the main camera
    std::shared_ptr<const MeshPreviewResult> result;
    QualityMetric metric = QualityMetric::ScaledJacobian;
    int slice = 0;
    std::array<bool, kMeshParts> visible{false, true, true, false};
    std::vector<GridCell> marked;
    GridCell focus;

    vtkNew<vtkLookupTable> lut;
    vtkNew<vtkScalarBarActor> bar;
    // Surfaces: wall, symmetry, slice.
    std::array<vtkNew<vtkPolyDataMapper>, 3> surfaceMappers;
    std::array<vtkNew<vtkActor>, 3> surfaces;
    vtkNew<vtkPolyDataMapper> controlMapper;
    vtkNew<vtkActor> control;
    vtkNew<vtkPolyDataMapper> markedMapper, focusMapper;
    vtkNew<vtkActor> markedActor, focusActor;

    static int surfaceIndex(MeshPart p) {
        return p == MeshPart::Wall ? 0 : p == MeshPart::Symmetry ? 1 : 2;
    }

    void buildSurfaces() {
        SurfaceBuilder wall, symmetry;
        const MeshPreviewResult& r = *result;
        for (std::size_t b = 0; b < r.grids.size() && b < r.mesh.blocks.size(); ++b) {
            const mesh::StructuredGrid& g = r.grids[b];
            for (int f = 0; f < 6; ++f) {
                const mesh::BoundaryKind kind =
                    r.mesh.blocks[b].faces[static_cast<std::size_t>(f)].kind;
                if (kind != mesh::BoundaryKind::Wall && kind != mesh::BoundaryKind::Symmetry)
                    continue;
                const int d = f / 2;
                const bool high = f % 2 == 1;
                const int n = g.dims[static_cast<std::size_t>(d)];
                (kind == mesh::BoundaryKind::Wall ? wall : symmetry)
                    .addPlane(g, r.quality[b], d, high ? n - 1 : 0, high ? n - 2 : 0);
            }
        }
        surfaceMappers[0]->SetInputData(wall.build());
        surfaceMappers[1]->SetInputData(symmetry.build());
        buildSlice();
    }

    void buildSlice() {
        SurfaceBuilder s;
        const MeshPreviewResult& r = *result;
        for (std::size_t b = 0; b < r.grids.size(); ++b) {
            const mesh::StructuredGrid& g = r.grids[b];
            const int layer = std::clamp(slice, 0, std::max(0, g.dims[2] - 2));
            s.addPlane(g, r.quality[b], 2, layer, layer);
        }
        surfaceMappers[2]->SetInputData(s.build());
    }

    void buildControlGrid() {
        const mesh::MultiBlockMesh& m = result->mesh;
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        points->SetNumberOfPoints(m.controlCount());
        for (vtkIdType n = 0; n < m.controlCount(); ++n)
            points->SetPoint(n, &m.control[3 * static_cast<std::size_t>(n)]);
        vtkNew<vtkCellArray> lines;
        std::vector<vtkIdType> ids;
        for (const mesh::ControlBlock& b : m.blocks) {
            for (int d = 0; d < 3; ++d) {
                const int a = d == 0 ? 1 : 0, c = d == 2 ? 1 : 2;
                const int nd = b.count[static_cast<std::size_t>(d)];
                ids.resize(static_cast<std::size_t>(nd));
                for (int jc = 0; jc < b.count[static_cast<std::size_t>(c)]; ++jc)
                    for (int ia = 0; ia < b.count[static_cast<std::size_t>(a)]; ++ia) {
                        std::array<int, 3> n{};
                        n[static_cast<std::size_t>(a)] = ia;
                        n[static_cast<std::size_t>(c)] = jc;
                        for (int t = 0; t < nd; ++t) {
                            n[static_cast<std::size_t>(d)] = t;
                            ids[static_cast<std::size_t>(t)] =
                                b.nodes[static_cast<std::size_t>(b.local(n[0], n[1], n[2]))];
                        }
                        lines->InsertNextCell(nd, ids.data());
                    }
            }
        }
        vtkNew<vtkPolyData> poly;
        poly->SetPoints(points);
        poly->SetLines(lines);
        controlMapper->SetInputData(poly);
    }

    void buildMarks(const std::vector<GridCell>& cells, vtkPolyDataMapper* mapper) {
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        vtkNew<vtkCellArray> verts, lines;
        for (const GridCell& c : cells)
            if (validCell(result.get(), c))
                addCellMark(result->grids[static_cast<std::size_t>(c.block)], c.cell, points, verts,
                            lines);
        vtkNew<vtkPolyData> poly;
        poly->SetPoints(points);
        poly->SetVerts(verts);
        poly->SetLines(lines);
        mapper->SetInputData(poly);
    }

    // The colour range of the metric: the data's finite range.
    void recolour() {
        double lo = 0, hi = 1;
        if (result) {
            const auto range = colourRange(result->summary, metric);
            lo = range[0];
            hi = range[1];
        }
        const bool logScale = useLogScale(metric, lo, hi);
        lut->SetScale(logScale ? VTK_SCALE_LOG10 : VTK_SCALE_LINEAR);
        lut->SetRange(lo, hi);
        lut->SetNumberOfTableValues(kColours);
        for (int i = 0; i < kColours; ++i) {
            const double t = static_cast<double>(i) / (kColours - 1);
            const auto c = qualityColour(higherIsBetter(metric) ? t : 1 - t);
            lut->SetTableValue(i, c[0], c[1], c[2], 1.0);
        }
        lut->SetNanColor(1.0, 0.0, 1.0, 1.0);
        lut->Modified();
        for (auto& m : surfaceMappers) {
            m->SelectColorArray(metricField(metric));
            m->Modified();
        }
        bar->SetTitle(metricLabel(metric));
    }

    void updateVisibility() {
        const bool has = result != nullptr;
        control->SetVisibility(has && visible[static_cast<std::size_t>(MeshPart::ControlGrid)]);
        bool coloured = false;
        for (MeshPart p : {MeshPart::Wall, MeshPart::Symmetry, MeshPart::Slice}) {
            const bool on = has && visible[static_cast<std::size_t>(p)];
            surfaces[static_cast<std::size_t>(surfaceIndex(p))]->SetVisibility(on);
            coloured = coloured || on;
        }
        bar->SetVisibility(coloured);
        markedActor->SetVisibility(has);
        focusActor->SetVisibility(has && focus.block >= 0);
    }
};

MeshScene::MeshScene(vtkRenderer* renderer) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.renderer = renderer;

    for (std::size_t s = 0; s < d.surfaces.size(); ++s) {
        vtkPolyDataMapper* m = d.surfaceMappers[s];
        m->SetLookupTable(d.lut);
        m->UseLookupTableScalarRangeOn();
        m->SetScalarModeToUseCellFieldData();
        m->SetColorModeToMapScalars();
        m->ScalarVisibilityOn();
        d.surfaces[s]->SetMapper(m);
        vtkProperty* p = d.surfaces[s]->GetProperty();
        p->EdgeVisibilityOn();
        p->SetEdgeColor(0.30, 0.32, 0.38);
        p->SetLineWidth(1.0f);
        p->SetAmbient(0.35);
        p->SetDiffuse(0.65);
        p->SetSpecular(0.0);
        d.surfaces[s]->PickableOff();
        renderer->AddActor(d.surfaces[s]);
    }

    d.control->SetMapper(d.controlMapper);
    d.controlMapper->ScalarVisibilityOff();
    vtkProperty* cp = d.control->GetProperty();
    cp->SetColor(0.36, 0.20, 0.55);
    cp->SetLineWidth(1.0f);
    cp->LightingOff();
    d.control->PickableOff();
    renderer->AddActor(d.control);

    d.bar->SetLookupTable(d.lut);
    d.bar->SetNumberOfLabels(5);
    d.bar->SetLabelFormat("%-#6.3g");
    d.bar->SetOrientationToHorizontal();
    d.bar->SetPosition(0.30, 0.015);
    d.bar->SetPosition2(0.45, 0.11);
    d.bar->SetBarRatio(0.28);
    d.bar->SetTextPositionToPrecedeScalarBar();  // labels under the bar, the title above it
    d.bar->UnconstrainedFontSizeOn();
    for (vtkTextProperty* t : {d.bar->GetTitleTextProperty(), d.bar->GetLabelTextProperty()}) {
        t->SetColor(0.15, 0.15, 0.18);
        t->ShadowOff();
        t->ItalicOff();
        t->SetFontSize(12);
    }
    d.bar->GetTitleTextProperty()->BoldOn();
    d.bar->GetTitleTextProperty()->SetFontSize(13);
    d.bar->SetVerticalTitleSeparation(6);
    renderer->AddActor2D(d.bar);

    // Marks: over everything, in a renderer of the next layer that shares the camera.
    for (auto [actor, mapper, rgb, size] :
         {std::tuple{d.markedActor.Get(), d.markedMapper.Get(),
                     std::array<double, 3>{0.90, 0.05, 0.05}, 11.0f},
          std::tuple{d.focusActor.Get(), d.focusMapper.Get(),
                     std::array<double, 3>{1.00, 0.85, 0.00}, 14.0f}}) {
        actor->SetMapper(mapper);
        mapper->ScalarVisibilityOff();
        vtkProperty* p = actor->GetProperty();
        p->SetColor(rgb.data());
        p->SetPointSize(size);
        p->SetLineWidth(3.0f);
        p->RenderPointsAsSpheresOn();
        p->LightingOff();
        actor->PickableOff();
        d.marks->AddActor(actor);
    }
    d.marks->SetLayer(kMarkLayer);
    d.marks->InteractiveOff();
    d.marks->SetActiveCamera(renderer->GetActiveCamera());
    if (vtkRenderWindow* window = renderer->GetRenderWindow()) {
        if (window->GetNumberOfLayers() <= kMarkLayer) window->SetNumberOfLayers(kMarkLayer + 1);
        window->AddRenderer(d.marks);
    }
    d.recolour();
    d.updateVisibility();
}

MeshScene::~MeshScene() {
    Impl& d = *d_;
    for (auto& s : d.surfaces) d.renderer->RemoveActor(s);
    d.renderer->RemoveActor(d.control);
    d.renderer->RemoveActor2D(d.bar);
    d.marks->RemoveAllViewProps();
    if (vtkRenderWindow* window = d.renderer->GetRenderWindow()) window->RemoveRenderer(d.marks);
}

void MeshScene::setResult(std::shared_ptr<const MeshPreviewResult> result) {
    Impl& d = *d_;
    d.result = std::move(result);
    d.marked.clear();
    d.focus = {};
    if (d.result) {
        d.slice = std::clamp(d.slice, 0, std::max(0, sliceLayers() - 1));
        d.buildSurfaces();
        d.buildControlGrid();
    } else {
        for (auto& m : d.surfaceMappers) m->SetInputData(vtkNew<vtkPolyData>());
        d.controlMapper->SetInputData(vtkNew<vtkPolyData>());
    }
    d.buildMarks({}, d.markedMapper);
    d.buildMarks({}, d.focusMapper);
    d.recolour();
    d.updateVisibility();
}

bool MeshScene::empty() const {
    return d_->result == nullptr;
}

const MeshPreviewResult* MeshScene::result() const {
    return d_->result.get();
}

void MeshScene::setMetric(QualityMetric metric) {
    d_->metric = metric;
    d_->recolour();
}

QualityMetric MeshScene::metric() const {
    return d_->metric;
}

void MeshScene::setSlice(int layer) {
    const int clamped = std::clamp(layer, 0, std::max(0, sliceLayers() - 1));
    if (clamped == d_->slice) return;
    d_->slice = clamped;
    if (d_->result) d_->buildSlice();
}

int MeshScene::slice() const {
    return d_->slice;
}

int MeshScene::sliceLayers() const {
    int layers = 0;
    if (d_->result)
        for (const auto& g : d_->result->grids) layers = std::max(layers, g.dims[2] - 1);
    return layers;
}

void MeshScene::setPartVisible(MeshPart part, bool visible) {
    d_->visible[static_cast<std::size_t>(part)] = visible;
    d_->updateVisibility();
}

bool MeshScene::partVisible(MeshPart part) const {
    return d_->visible[static_cast<std::size_t>(part)];
}

bool MeshScene::anythingVisible() const {
    return d_->result &&
           std::any_of(d_->visible.begin(), d_->visible.end(), [](bool v) { return v; });
}

void MeshScene::setMarkedCells(const std::vector<GridCell>& cells) {
    d_->marked = cells;
    d_->buildMarks(cells, d_->markedMapper);
}

int MeshScene::markedCellCount() const {
    return static_cast<int>(d_->marked.size());
}

void MeshScene::setFocusCell(const GridCell& cell) {
    d_->focus = validCell(d_->result.get(), cell) ? cell : GridCell{};
    d_->buildMarks(
        d_->focus.block >= 0 ? std::vector<GridCell>{d_->focus} : std::vector<GridCell>{},
        d_->focusMapper);
    d_->updateVisibility();
}

GridCell MeshScene::focusCell() const {
    return d_->focus;
}

bool MeshScene::cellCentre(const GridCell& cell, std::array<double, 3>& centre,
                           double& size) const {
    if (!validCell(d_->result.get(), cell)) return false;
    const auto& g = d_->result->grids[static_cast<std::size_t>(cell.block)];
    std::array<const double*, 8> x{};
    centre = {0, 0, 0};
    for (int corner = 0; corner < 8; ++corner) {
        x[static_cast<std::size_t>(corner)] =
            g.at(cell.cell[0] + (corner & 1), cell.cell[1] + ((corner >> 1) & 1),
                 cell.cell[2] + ((corner >> 2) & 1));
        for (int k = 0; k < 3; ++k)
            centre[static_cast<std::size_t>(k)] += x[static_cast<std::size_t>(corner)][k] / 8;
    }
    size = 0;
    for (std::size_t a = 0; a < 8; ++a)
        for (std::size_t b = a + 1; b < 8; ++b)
            size =
                std::max(size, std::hypot(x[a][0] - x[b][0], x[a][1] - x[b][1], x[a][2] - x[b][2]));
    return true;
}

std::array<double, 6> MeshScene::wallBounds() const {
    std::array<double, 6> b{0, 0, 0, 0, 0, 0};
    if (!d_->result) return b;
    vtkDataSet* wall = d_->surfaceMappers[0]->GetInput();
    if (!wall || wall->GetNumberOfPoints() == 0) return b;
    wall->GetBounds(b.data());
    return b;
}

}  // namespace aero::ui
