#include "FlowScene.h"

#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkContourFilter.h>
#include <vtkCutter.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkStripper.h>
#include <vtkStructuredGrid.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "flow/FlowMesh.h"

namespace aero::ui {

namespace {

constexpr int kColours = 256;

// ASCII titles: VTK's embedded fonts lack the symbols of flowFieldLabel.
const char* barTitleFor(FlowField f) {
    switch (f) {
        case FlowField::Entropy:
            return "Entropy s-s_inf";
        case FlowField::PressureCoefficient:
            return "Cp";
        case FlowField::Mach:
            return "Mach";
        case FlowField::Pressure:
            return "Pressure p";
    }
    return "";
}

vtkSmartPointer<vtkDoubleArray> fieldArray(FlowField f) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(flowFieldKey(f));
    return a;
}

// Faces of one boundary kind as quads with the fields at their nodes.
vtkSmartPointer<vtkPolyData> boundarySurface(const FlowRunResult& r, mesh::BoundaryKind kind) {
    const study::FlowResult& fr = *r.flow;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> quads;
    std::array<vtkSmartPointer<vtkDoubleArray>, kFlowFields> arrays;
    for (int f = 0; f < kFlowFields; ++f) arrays[static_cast<std::size_t>(f)] = fieldArray(static_cast<FlowField>(f));
    for (const flow::FlowBlock& b : fr.mesh.blocks) {
        for (int f = 0; f < 6; ++f) {
            if (b.faces[static_cast<std::size_t>(f)].kind != kind) continue;
            const int d = flow::faceDirection(f);
            const int a = d == 0 ? 1 : 0, c = d == 2 ? 1 : 2;
            const int na = b.dims[static_cast<std::size_t>(a)], nc = b.dims[static_cast<std::size_t>(c)];
            const vtkIdType base = points->GetNumberOfPoints();
            for (long local : flow::faceNodes(b.dims, f)) {
                const std::size_t n = static_cast<std::size_t>(b.offset + local);
                points->InsertNextPoint(&fr.x[3 * n]);
                for (int k = 0; k < kFlowFields; ++k)
                    arrays[static_cast<std::size_t>(k)]->InsertNextValue(r.fields[static_cast<std::size_t>(k)][n]);
            }
            for (int jc = 0; jc + 1 < nc; ++jc)
                for (int ia = 0; ia + 1 < na; ++ia) {
                    const vtkIdType p = base + ia + static_cast<vtkIdType>(na) * jc;
                    const vtkIdType ids[4] = {p, p + 1, p + 1 + na, p + na};
                    quads->InsertNextCell(4, ids);
                }
        }
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetPolys(quads);
    for (auto& a : arrays) poly->GetPointData()->AddArray(a);
    return poly;
}

// Every block as a structured grid with the fields (for the slice).
std::vector<vtkSmartPointer<vtkStructuredGrid>> blockGrids(const FlowRunResult& r) {
    const study::FlowResult& fr = *r.flow;
    std::vector<vtkSmartPointer<vtkStructuredGrid>> out;
    for (const flow::FlowBlock& b : fr.mesh.blocks) {
        auto g = vtkSmartPointer<vtkStructuredGrid>::New();
        g->SetDimensions(b.dims[0], b.dims[1], b.dims[2]);
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        points->SetNumberOfPoints(b.nodeCount());
        std::array<vtkSmartPointer<vtkDoubleArray>, kFlowFields> arrays;
        for (int f = 0; f < kFlowFields; ++f) {
            arrays[static_cast<std::size_t>(f)] = fieldArray(static_cast<FlowField>(f));
            arrays[static_cast<std::size_t>(f)]->SetNumberOfValues(b.nodeCount());
        }
        for (long local = 0; local < b.nodeCount(); ++local) {  // i fastest, as VTK's structured order
            const std::size_t n = static_cast<std::size_t>(b.offset + local);
            points->SetPoint(local, &fr.x[3 * n]);
            for (int k = 0; k < kFlowFields; ++k)
                arrays[static_cast<std::size_t>(k)]->SetValue(local, r.fields[static_cast<std::size_t>(k)][n]);
        }
        g->SetPoints(points);
        for (auto& a : arrays) g->GetPointData()->AddArray(a);
        out.push_back(g);
    }
    return out;
}

}  // namespace

std::array<double, 2> SectionCut::xRange() const {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& piece : pieces)
        for (const auto& p : piece) {
            lo = std::min(lo, p[0]);
            hi = std::max(hi, p[0]);
        }
    return lo <= hi ? std::array<double, 2>{lo, hi} : std::array<double, 2>{0, 0};
}

struct FlowScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    std::shared_ptr<const FlowRunResult> result;
    FlowField field = FlowField::Entropy;
    std::optional<std::pair<double, double>> manualRange;
    int contours = 12;
    std::array<bool, kFlowParts> visible{true, true, false, false, true};
    int sliceAxis = 1;
    double slicePosition = 0;
    bool shown = true;
    bool barShown = true;

    vtkNew<vtkLookupTable> lut;
    vtkNew<vtkScalarBarActor> bar;
    // Surfaces: wall, symmetry, slice (the field's colours) and their contour lines.
    std::array<vtkSmartPointer<vtkPolyData>, 3> surfaces;
    vtkNew<vtkPolyDataNormals> wallNormals;
    std::array<vtkNew<vtkPolyDataMapper>, 3> surfaceMappers;
    std::array<vtkNew<vtkActor>, 3> surfaceActors;
    std::array<vtkNew<vtkContourFilter>, 3> contourFilters;
    std::array<vtkNew<vtkPolyDataMapper>, 3> contourMappers;
    std::array<vtkNew<vtkActor>, 3> contourActors;
    std::vector<vtkSmartPointer<vtkStructuredGrid>> blocks;  // for the slice, built when first needed
    vtkNew<vtkPolyDataMapper> sectionMapper;
    vtkNew<vtkActor> sectionActor;

    static std::size_t partSurface(FlowPart p) { return p == FlowPart::Wall ? 0 : p == FlowPart::Symmetry ? 1 : 2; }

    std::array<std::pair<double, double>, kFlowFields> autoRanges{};  // per field, for the result

    // The automatic colour range of field f: its range on the wall and the symmetry plane (the
    // whole grid's without them); for the entropy the 1st to 99th percentile, since a few nodes
    // at a blunt trailing edge or a stagnation point carry most of the error and would wash out
    // everything else (beyond the range the end colours are used).
    std::pair<double, double> computeAutoRange(FlowField f) const {
        std::vector<double> values;
        for (std::size_t s = 0; s < 2; ++s) {
            vtkDataArray* a = surfaces[s] ? surfaces[s]->GetPointData()->GetArray(flowFieldKey(f)) : nullptr;
            if (!a) continue;
            for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i) {
                const double v = a->GetTuple1(i);
                if (std::isfinite(v)) values.push_back(v);
            }
        }
        double lo = 0, hi = 0;
        if (values.empty()) {
            lo = result->range[static_cast<std::size_t>(f)][0];
            hi = result->range[static_cast<std::size_t>(f)][1];
        } else if (f == FlowField::Entropy && values.size() >= 100) {
            const auto at = [&values](double q) {
                const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
                std::nth_element(values.begin(), values.begin() + k, values.end());
                return values[static_cast<std::size_t>(k)];
            };
            lo = at(0.01);
            hi = at(0.99);
        } else {
            const auto [mn, mx] = std::minmax_element(values.begin(), values.end());
            lo = *mn;
            hi = *mx;
        }
        if (!(hi > lo)) {
            const double pad = std::max(1e-12, 1e-6 * std::abs(lo));
            lo -= pad;
            hi += pad;
        }
        return {lo, hi};
    }

    std::pair<double, double> autoRange(FlowField f) const {
        return result ? autoRanges[static_cast<std::size_t>(f)] : std::pair<double, double>{0.0, 1.0};
    }

    std::pair<double, double> range() const { return manualRange ? *manualRange : autoRange(field); }

    void buildSlice() {
        if (!result || !visible[static_cast<std::size_t>(FlowPart::Slice)]) {
            surfaces[2] = vtkSmartPointer<vtkPolyData>::New();
        } else {
            if (blocks.empty()) blocks = blockGrids(*result);
            vtkNew<vtkPlane> plane;
            double origin[3] = {0, 0, 0}, normal[3] = {0, 0, 0};
            origin[sliceAxis] = slicePosition;
            normal[sliceAxis] = 1;
            plane->SetOrigin(origin);
            plane->SetNormal(normal);
            vtkNew<vtkAppendPolyData> append;
            int pieces = 0;
            for (auto& g : blocks) {
                double b[6];
                g->GetBounds(b);
                if (slicePosition < b[2 * sliceAxis] || slicePosition > b[2 * sliceAxis + 1]) continue;
                vtkNew<vtkCutter> cutter;
                cutter->SetCutFunction(plane);
                cutter->SetInputData(g);
                cutter->Update();
                auto out = vtkSmartPointer<vtkPolyData>::New();
                out->ShallowCopy(cutter->GetOutput());
                append->AddInputData(out);
                ++pieces;
            }
            if (pieces > 0) {
                append->Update();
                surfaces[2] = vtkSmartPointer<vtkPolyData>::New();
                surfaces[2]->ShallowCopy(append->GetOutput());
            } else {
                surfaces[2] = vtkSmartPointer<vtkPolyData>::New();
            }
        }
        surfaceMappers[2]->SetInputData(surfaces[2]);
        contourFilters[2]->SetInputData(surfaces[2]);
    }

    void recolour() {
        const auto [lo, hi] = range();
        lut->SetRange(lo, hi);
        lut->SetNumberOfTableValues(kColours);
        for (int i = 0; i < kColours; ++i) {
            const auto c = fieldColour(static_cast<double>(i) / (kColours - 1));
            lut->SetTableValue(i, c[0], c[1], c[2], 1.0);
        }
        lut->SetNanColor(1.0, 0.0, 1.0, 1.0);
        lut->Modified();
        for (auto& m : surfaceMappers) {
            m->SelectColorArray(flowFieldKey(field));
            m->Modified();
        }
        bar->SetTitle(barTitleFor(field));
        const int n = std::max(0, contours);
        for (auto& c : contourFilters) {
            c->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, flowFieldKey(field));
            c->SetNumberOfContours(n);
            for (int i = 0; i < n; ++i) c->SetValue(i, lo + (hi - lo) * (i + 1.0) / (n + 1.0));
            c->Modified();
        }
    }

    void updateVisibility() {
        const bool has = result != nullptr && shown;
        bool coloured = false;
        for (FlowPart p : {FlowPart::Wall, FlowPart::Symmetry, FlowPart::Slice}) {
            const bool on = has && visible[static_cast<std::size_t>(p)];
            const std::size_t s = partSurface(p);
            surfaceActors[s]->SetVisibility(on);
            contourActors[s]->SetVisibility(on && visible[static_cast<std::size_t>(FlowPart::Contours)] && contours > 0);
            coloured = coloured || on;
        }
        bar->SetVisibility(coloured && barShown);
        sectionActor->SetVisibility(has && visible[static_cast<std::size_t>(FlowPart::Sections)]);
    }
};

FlowScene::FlowScene(vtkRenderer* renderer) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.renderer = renderer;
    for (auto& s : d.surfaces) s = vtkSmartPointer<vtkPolyData>::New();
    d.wallNormals->ComputePointNormalsOn();
    d.wallNormals->ComputeCellNormalsOff();
    d.wallNormals->SplittingOff();
    d.wallNormals->ConsistencyOn();
    d.wallNormals->SetInputData(d.surfaces[0]);
    for (std::size_t s = 0; s < 3; ++s) {
        vtkPolyDataMapper* m = d.surfaceMappers[s];
        if (s == 0)
            m->SetInputConnection(d.wallNormals->GetOutputPort());
        else
            m->SetInputData(d.surfaces[s]);
        m->SetLookupTable(d.lut);
        m->UseLookupTableScalarRangeOn();
        m->SetScalarModeToUsePointFieldData();
        m->SetColorModeToMapScalars();
        m->ScalarVisibilityOn();
        m->InterpolateScalarsBeforeMappingOn();  // sharp colour steps instead of smeared RGB
        m->SetRelativeCoincidentTopologyPolygonOffsetParameters(1.5, 1.5);  // contour lines on top
        d.surfaceActors[s]->SetMapper(m);
        vtkProperty* p = d.surfaceActors[s]->GetProperty();
        p->SetAmbient(0.35);
        p->SetDiffuse(0.7);
        p->SetSpecular(0.05);
        d.surfaceActors[s]->PickableOff();
        renderer->AddActor(d.surfaceActors[s]);

        d.contourFilters[s]->SetInputData(d.surfaces[s]);
        d.contourFilters[s]->ComputeScalarsOff();
        d.contourFilters[s]->ComputeNormalsOff();
        d.contourMappers[s]->SetInputConnection(d.contourFilters[s]->GetOutputPort());
        d.contourMappers[s]->ScalarVisibilityOff();
        d.contourActors[s]->SetMapper(d.contourMappers[s]);
        vtkProperty* cp = d.contourActors[s]->GetProperty();
        cp->SetColor(0.12, 0.12, 0.16);
        cp->SetLineWidth(1.2f);
        cp->LightingOff();
        d.contourActors[s]->PickableOff();
        renderer->AddActor(d.contourActors[s]);
    }
    d.sectionActor->SetMapper(d.sectionMapper);
    d.sectionMapper->ScalarVisibilityOff();
    d.sectionMapper->SetInputData(vtkNew<vtkPolyData>());
    vtkProperty* sp = d.sectionActor->GetProperty();
    sp->SetColor(0.05, 0.05, 0.08);
    sp->SetLineWidth(2.5f);
    sp->LightingOff();
    d.sectionActor->PickableOff();
    renderer->AddActor(d.sectionActor);

    d.bar->SetLookupTable(d.lut);
    d.bar->SetNumberOfLabels(5);
    d.bar->SetLabelFormat("%-#6.3g");
    d.bar->SetOrientationToVertical();
    d.bar->SetPosition(0.86, 0.18);
    d.bar->SetPosition2(0.12, 0.64);
    d.bar->SetBarRatio(0.25);
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
    d.recolour();
    d.updateVisibility();
}

FlowScene::~FlowScene() {
    Impl& d = *d_;
    for (auto& a : d.surfaceActors) d.renderer->RemoveActor(a);
    for (auto& a : d.contourActors) d.renderer->RemoveActor(a);
    d.renderer->RemoveActor(d.sectionActor);
    d.renderer->RemoveActor2D(d.bar);
}

void FlowScene::setResult(std::shared_ptr<const FlowRunResult> result) {
    Impl& d = *d_;
    d.result = result && result->flow && !result->fields[0].empty() ? std::move(result) : nullptr;
    d.blocks.clear();
    if (d.result) {
        d.surfaces[0] = boundarySurface(*d.result, mesh::BoundaryKind::Wall);
        d.surfaces[1] = boundarySurface(*d.result, mesh::BoundaryKind::Symmetry);
    } else {
        d.surfaces[0] = vtkSmartPointer<vtkPolyData>::New();
        d.surfaces[1] = vtkSmartPointer<vtkPolyData>::New();
    }
    d.wallNormals->SetInputData(d.surfaces[0]);
    d.surfaceMappers[1]->SetInputData(d.surfaces[1]);
    if (d.result)
        for (int f = 0; f < kFlowFields; ++f)
            d.autoRanges[static_cast<std::size_t>(f)] = d.computeAutoRange(static_cast<FlowField>(f));
    for (std::size_t s = 0; s < 2; ++s) d.contourFilters[s]->SetInputData(d.surfaces[s]);
    d.buildSlice();
    d.sectionMapper->SetInputData(vtkNew<vtkPolyData>());
    d.recolour();
    d.updateVisibility();
}

bool FlowScene::empty() const {
    return d_->result == nullptr;
}

const FlowRunResult* FlowScene::result() const {
    return d_->result.get();
}

void FlowScene::setField(FlowField field) {
    d_->field = field;
    d_->recolour();
}

FlowField FlowScene::field() const {
    return d_->field;
}

void FlowScene::setRange(std::optional<std::pair<double, double>> range) {
    if (range && !(range->second > range->first)) range.reset();
    d_->manualRange = range;
    d_->recolour();
}

std::pair<double, double> FlowScene::range() const {
    return d_->range();
}

std::pair<double, double> FlowScene::autoRange(FlowField field) const {
    return d_->autoRange(field);
}

std::string FlowScene::barTitle() const {
    const char* t = d_->bar->GetTitle();
    return t ? t : "";
}

void FlowScene::setContourCount(int count) {
    d_->contours = std::max(0, count);
    d_->recolour();
    d_->updateVisibility();
}

int FlowScene::contourCount() const {
    return d_->contours;
}

void FlowScene::setPartVisible(FlowPart part, bool visible) {
    Impl& d = *d_;
    const bool was = d.visible[static_cast<std::size_t>(part)];
    d.visible[static_cast<std::size_t>(part)] = visible;
    if (part == FlowPart::Slice && was != visible) d.buildSlice();
    d.updateVisibility();
}

bool FlowScene::partVisible(FlowPart part) const {
    return d_->visible[static_cast<std::size_t>(part)];
}

bool FlowScene::wallShown() const {
    return d_->result && d_->shown && d_->visible[static_cast<std::size_t>(FlowPart::Wall)];
}

void FlowScene::setShown(bool shown) {
    d_->shown = shown;
    d_->updateVisibility();
}

bool FlowScene::shown() const {
    return d_->shown;
}

void FlowScene::setColourBarShown(bool shown) {
    d_->barShown = shown;
    d_->updateVisibility();
}

void FlowScene::setOffset(const std::array<double, 3>& offset) {
    Impl& d = *d_;
    for (auto& a : d.surfaceActors) a->SetPosition(offset[0], offset[1], offset[2]);
    for (auto& a : d.contourActors) a->SetPosition(offset[0], offset[1], offset[2]);
    d.sectionActor->SetPosition(offset[0], offset[1], offset[2]);
}

void FlowScene::setSlice(int axis, double position) {
    Impl& d = *d_;
    d.sliceAxis = std::clamp(axis, 0, 2);
    d.slicePosition = position;
    d.buildSlice();
    d.updateVisibility();
}

int FlowScene::sliceAxis() const {
    return d_->sliceAxis;
}

double FlowScene::slicePosition() const {
    return d_->slicePosition;
}

std::vector<SectionCut> FlowScene::cutWall(const std::vector<double>& stations, FlowField field) {
    Impl& d = *d_;
    std::vector<SectionCut> cuts;
    vtkNew<vtkAppendPolyData> lines;
    int drawn = 0;
    const auto b = wallBounds();
    const double span = b[3] - b[2];
    for (double station : stations) {
        SectionCut cut;
        cut.station = station;
        if (d.result && d.surfaces[0]->GetNumberOfCells() > 0 && span > 0) {
            // A cut exactly on the wall's edge (the symmetry plane) would be degenerate.
            const double y = std::clamp(station, b[2] + 1e-4 * span, b[3] - 1e-4 * span);
            vtkNew<vtkPlane> plane;
            plane->SetOrigin(0, y, 0);
            plane->SetNormal(0, 1, 0);
            vtkNew<vtkCutter> cutter;
            cutter->SetCutFunction(plane);
            cutter->SetInputData(d.surfaces[0]);
            vtkNew<vtkStripper> stripper;
            stripper->SetInputConnection(cutter->GetOutputPort());
            stripper->JoinContiguousSegmentsOn();
            stripper->Update();
            vtkPolyData* out = stripper->GetOutput();
            vtkDataArray* values = out->GetPointData()->GetArray(flowFieldKey(field));
            vtkCellArray* polylines = out->GetLines();
            vtkNew<vtkIdList> ids;
            polylines->InitTraversal();
            while (polylines->GetNextCell(ids)) {
                std::vector<std::array<double, 3>> piece;
                for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i) {
                    double x[3];
                    out->GetPoint(ids->GetId(i), x);
                    piece.push_back({x[0], x[2], values ? values->GetTuple1(ids->GetId(i)) : 0.0});
                }
                if (piece.size() >= 2) cut.pieces.push_back(std::move(piece));
            }
            if (out->GetNumberOfLines() > 0) {
                auto copy = vtkSmartPointer<vtkPolyData>::New();
                copy->DeepCopy(out);
                lines->AddInputData(copy);
                ++drawn;
            }
        }
        cuts.push_back(std::move(cut));
    }
    if (drawn > 0) {
        lines->Update();
        auto all = vtkSmartPointer<vtkPolyData>::New();
        all->ShallowCopy(lines->GetOutput());
        d.sectionMapper->SetInputData(all);
    } else {
        d.sectionMapper->SetInputData(vtkNew<vtkPolyData>());
    }
    d.updateVisibility();
    return cuts;
}

std::array<double, 6> FlowScene::wallBounds() const {
    std::array<double, 6> b{0, 0, 0, 0, 0, 0};
    if (!d_->result || d_->surfaces[0]->GetNumberOfPoints() == 0) return b;
    d_->surfaces[0]->GetBounds(b.data());
    return b;
}

std::array<double, 6> FlowScene::gridBounds() const {
    std::array<double, 6> b{0, 0, 0, 0, 0, 0};
    if (!d_->result) return b;
    const std::vector<double>& x = d_->result->flow->x;
    if (x.empty()) return b;
    for (int k = 0; k < 3; ++k) {
        b[static_cast<std::size_t>(2 * k)] = std::numeric_limits<double>::infinity();
        b[static_cast<std::size_t>(2 * k + 1)] = -std::numeric_limits<double>::infinity();
    }
    for (std::size_t n = 0; n + 2 < x.size(); n += 3)
        for (std::size_t k = 0; k < 3; ++k) {
            b[2 * k] = std::min(b[2 * k], x[n + k]);
            b[2 * k + 1] = std::max(b[2 * k + 1], x[n + k]);
        }
    return b;
}

long FlowScene::sliceCells() const {
    if (!d_->result || !d_->visible[static_cast<std::size_t>(FlowPart::Slice)]) return 0;
    return static_cast<long>(d_->surfaces[2]->GetNumberOfCells());
}

long FlowScene::contourSegments() const {
    long n = 0;
    for (std::size_t s = 0; s < 3; ++s) {
        if (!d_->contourActors[s]->GetVisibility()) continue;
        d_->contourFilters[s]->Update();
        n += static_cast<long>(d_->contourFilters[s]->GetOutput()->GetNumberOfLines());
    }
    return n;
}

}  // namespace aero::ui
