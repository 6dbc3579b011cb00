#include "LatticeScene.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>

namespace aero::ui {

namespace {

using Rgb = std::array<unsigned char, 3>;
constexpr Rgb kPoint{18, 121, 130};      // teal
constexpr Rgb kDisplaced{232, 118, 20};  // orange
constexpr Rgb kLine{70, 96, 112};        // slate
constexpr Rgb kFolded{214, 32, 32};      // red

vtkSmartPointer<vtkUnsignedCharArray> colorArray(const char* name) {
    auto a = vtkSmartPointer<vtkUnsignedCharArray>::New();
    a->SetName(name);
    a->SetNumberOfComponents(3);
    return a;
}

void styleActor(vtkActor* actor, vtkPolyDataMapper* mapper, float pointSize, float lineWidth) {
    actor->SetMapper(mapper);
    vtkProperty* p = actor->GetProperty();
    p->SetPointSize(pointSize);
    p->SetLineWidth(lineWidth);
    p->RenderPointsAsSpheresOn();
    p->LightingOff();
    actor->PickableOff();
}

}  // namespace

struct LatticeScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    vtkNew<vtkPolyDataMapper> pointMapper, lineMapper, selectedMapper, foldMapper;
    vtkNew<vtkActor> points, lines, selected, folds;
    std::vector<LatticeView> lattices;
    std::vector<char> visible;
    bool allVisible = true;
    int selectedLattice = -1;
    std::vector<int> selectedPoints;
};

LatticeScene::LatticeScene(vtkRenderer* renderer) : d_(std::make_unique<Impl>()) {
    d_->renderer = renderer;
    for (vtkPolyDataMapper* m : {d_->pointMapper.Get(), d_->lineMapper.Get()}) {
        m->SetColorModeToDirectScalars();
        m->ScalarVisibilityOn();
    }
    d_->pointMapper->SetScalarModeToUsePointData();
    d_->lineMapper->SetScalarModeToUseCellData();
    d_->selectedMapper->ScalarVisibilityOff();
    d_->foldMapper->ScalarVisibilityOff();
    styleActor(d_->points, d_->pointMapper, 10.0f, 1.0f);
    styleActor(d_->lines, d_->lineMapper, 1.0f, 1.6f);
    styleActor(d_->selected, d_->selectedMapper, 15.0f, 1.0f);
    d_->selected->GetProperty()->SetColor(1.0, 0.85, 0.05);
    styleActor(d_->folds, d_->foldMapper, 22.0f, 1.0f);
    d_->folds->GetProperty()->SetColor(kFolded[0] / 255.0, kFolded[1] / 255.0, kFolded[2] / 255.0);
    d_->folds->GetProperty()->SetOpacity(0.85);
    // Lines are drawn slightly behind points at equal depth (points sit on the line ends).
    d_->lineMapper->SetRelativeCoincidentTopologyLineOffsetParameters(0, 2);
    for (vtkActor* a : {d_->lines.Get(), d_->points.Get(), d_->selected.Get(), d_->folds.Get()}) renderer->AddActor(a);
    rebuild();
}

LatticeScene::~LatticeScene() {
    for (vtkActor* a : {d_->lines.Get(), d_->points.Get(), d_->selected.Get(), d_->folds.Get()})
        d_->renderer->RemoveActor(a);
}

void LatticeScene::setLattices(std::vector<LatticeView> lattices) {
    const std::size_t before = d_->lattices.size();
    d_->lattices = std::move(lattices);
    if (d_->lattices.size() != before) d_->visible.assign(d_->lattices.size(), 1);
    if (d_->selectedLattice >= static_cast<int>(d_->lattices.size())) {
        d_->selectedLattice = -1;
        d_->selectedPoints.clear();
    }
    rebuild();
}

void LatticeScene::clear() {
    d_->lattices.clear();
    d_->visible.clear();
    d_->selectedLattice = -1;
    d_->selectedPoints.clear();
    rebuild();
}

void LatticeScene::setSelection(int lattice, const std::vector<int>& points) {
    d_->selectedLattice = lattice;
    d_->selectedPoints = lattice >= 0 ? points : std::vector<int>{};
    rebuild();
}

void LatticeScene::setVisible(bool visible) {
    d_->allVisible = visible;
    rebuild();
}

bool LatticeScene::visible() const {
    return d_->allVisible;
}

void LatticeScene::setLatticeVisible(int lattice, bool visible) {
    if (lattice < 0 || lattice >= latticeCount()) return;
    d_->visible[static_cast<std::size_t>(lattice)] = visible ? 1 : 0;
    rebuild();
}

bool LatticeScene::latticeVisible(int lattice) const {
    return d_->allVisible && lattice >= 0 && lattice < latticeCount() && d_->visible[static_cast<std::size_t>(lattice)] != 0;
}

int LatticeScene::latticeCount() const {
    return static_cast<int>(d_->lattices.size());
}

const ffd::Lattice& LatticeScene::lattice(int l) const {
    return d_->lattices[static_cast<std::size_t>(l)].lattice;
}

std::vector<double> LatticeScene::allPoints() const {
    std::vector<double> out;
    for (int l = 0; l < latticeCount(); ++l)
        if (latticeVisible(l)) {
            const auto& p = lattice(l).points;
            out.insert(out.end(), p.begin(), p.end());
        }
    return out;
}

void LatticeScene::rebuild() {
    Impl& d = *d_;
    vtkNew<vtkPoints> pts, selPts, foldPts;
    pts->SetDataTypeToDouble();
    vtkNew<vtkCellArray> verts, lines, selVerts, foldVerts;
    auto pointColors = colorArray("Colors");
    auto lineColors = colorArray("Colors");

    for (int l = 0; l < latticeCount(); ++l) {
        if (!latticeVisible(l)) continue;
        const LatticeView& view = d.lattices[static_cast<std::size_t>(l)];
        const ffd::Lattice& L = view.lattice;
        const vtkIdType base = pts->GetNumberOfPoints();
        std::vector<char> displaced(static_cast<std::size_t>(L.controlCount()), 0);
        for (int a : view.displaced)
            if (a >= 0 && a < L.controlCount()) displaced[static_cast<std::size_t>(a)] = 1;
        for (int a = 0; a < L.controlCount(); ++a) {
            const double* x = &L.points[3 * static_cast<std::size_t>(a)];
            pts->InsertNextPoint(x);
            const vtkIdType id = base + a;
            verts->InsertNextCell(1, &id);
            pointColors->InsertNextTypedTuple(displaced[static_cast<std::size_t>(a)] ? kDisplaced.data() : kPoint.data());
        }
        const Rgb& lineRgb = view.injective ? kLine : kFolded;
        // Lines of the net along each direction d: vary index d, fix the other two.
        for (int dir = 0; dir < 3; ++dir) {
            const int e = (dir + 1) % 3, f = (dir + 2) % 3;
            for (int jf = 0; jf < L.count[static_cast<std::size_t>(f)]; ++jf)
                for (int je = 0; je < L.count[static_cast<std::size_t>(e)]; ++je) {
                    std::vector<vtkIdType> ids;
                    for (int i = 0; i < L.count[static_cast<std::size_t>(dir)]; ++i) {
                        std::array<int, 3> idx{};
                        idx[static_cast<std::size_t>(dir)] = i;
                        idx[static_cast<std::size_t>(e)] = je;
                        idx[static_cast<std::size_t>(f)] = jf;
                        ids.push_back(base + L.index(idx[0], idx[1], idx[2]));
                    }
                    lines->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
                    lineColors->InsertNextTypedTuple(lineRgb.data());
                }
        }
        if (!view.injective) {
            const vtkIdType id = foldPts->InsertNextPoint(view.foldAt.data());
            foldVerts->InsertNextCell(1, &id);
        }
        if (l == d.selectedLattice) {
            for (int a : d.selectedPoints) {
                if (a < 0 || a >= L.controlCount()) continue;
                const vtkIdType id = selPts->InsertNextPoint(&L.points[3 * static_cast<std::size_t>(a)]);
                selVerts->InsertNextCell(1, &id);
            }
        }
    }

    vtkNew<vtkPolyData> pointPoly, linePoly, selPoly, foldPoly;
    pointPoly->SetPoints(pts);
    pointPoly->SetVerts(verts);
    pointPoly->GetPointData()->SetScalars(pointColors);
    linePoly->SetPoints(pts);
    linePoly->SetLines(lines);
    linePoly->GetCellData()->SetScalars(lineColors);
    selPoly->SetPoints(selPts);
    selPoly->SetVerts(selVerts);
    foldPoly->SetPoints(foldPts);
    foldPoly->SetVerts(foldVerts);
    d.pointMapper->SetInputData(pointPoly);
    d.lineMapper->SetInputData(linePoly);
    d.selectedMapper->SetInputData(selPoly);
    d.foldMapper->SetInputData(foldPoly);
}

}  // namespace aero::ui
