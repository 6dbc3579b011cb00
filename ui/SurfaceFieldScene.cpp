#include "SurfaceFieldScene.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>

namespace aero::ui {

namespace {

constexpr int kColours = 256;

// Blue (negative), white (zero), red (positive): a diverging scale for a signed field.
void fillDiverging(vtkLookupTable* lut) {
    static constexpr double kBlue[3] = {0.17, 0.35, 0.75}, kWhite[3] = {0.97, 0.97, 0.97}, kRed[3] = {0.78, 0.15, 0.13};
    lut->SetNumberOfTableValues(kColours);
    for (int i = 0; i < kColours; ++i) {
        const double t = static_cast<double>(i) / (kColours - 1);
        const double* a = t < 0.5 ? kBlue : kWhite;
        const double* b = t < 0.5 ? kWhite : kRed;
        const double s = t < 0.5 ? 2 * t : 2 * t - 1;
        lut->SetTableValue(i, (1 - s) * a[0] + s * b[0], (1 - s) * a[1] + s * b[1], (1 - s) * a[2] + s * b[2], 1.0);
    }
    lut->Modified();
}

}  // namespace

struct SurfaceFieldScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    vtkNew<vtkPolyDataMapper> mapper;
    vtkNew<vtkActor> actor;
    vtkNew<vtkLookupTable> lut;
    vtkNew<vtkScalarBarActor> bar;
    int points = 0;
    double largest = 0;
    std::string title;
};

SurfaceFieldScene::SurfaceFieldScene(vtkRenderer* renderer) : d_(std::make_unique<Impl>()) {
    d_->renderer = renderer;
    fillDiverging(d_->lut);
    d_->mapper->SetLookupTable(d_->lut);
    d_->mapper->UseLookupTableScalarRangeOn();
    d_->mapper->SetScalarModeToUsePointData();
    d_->mapper->ScalarVisibilityOn();
    // In front of the geometry's surfaces, which lie in the same place.
    d_->mapper->SetRelativeCoincidentTopologyPolygonOffsetParameters(-2, -2);
    d_->actor->SetMapper(d_->mapper);
    vtkProperty* p = d_->actor->GetProperty();
    p->SetInterpolationToPhong();
    p->SetAmbient(0.3);
    p->SetDiffuse(0.7);
    d_->actor->PickableOff();

    d_->bar->SetLookupTable(d_->lut);
    d_->bar->SetNumberOfLabels(5);
    d_->bar->SetLabelFormat("%-#6.2g");
    d_->bar->SetOrientationToVertical();
    d_->bar->SetPosition(0.03, 0.28);  // left, above the orientation axes: the flow field's bar is on the right
    d_->bar->SetPosition2(0.13, 0.58);
    d_->bar->SetBarRatio(0.22);
    d_->bar->UnconstrainedFontSizeOn();
    for (vtkTextProperty* t : {d_->bar->GetTitleTextProperty(), d_->bar->GetLabelTextProperty()}) {
        t->SetColor(0.15, 0.15, 0.18);
        t->ShadowOff();
        t->ItalicOff();
        t->SetFontSize(12);
    }
    d_->bar->GetTitleTextProperty()->BoldOn();
    d_->bar->SetTextPositionToSucceedScalarBar();  // labels right of the bar, inside the view
    d_->bar->SetVerticalTitleSeparation(6);
    d_->bar->PickableOff();
    renderer->AddActor(d_->actor);
    renderer->AddActor2D(d_->bar);
    clear();
}

SurfaceFieldScene::~SurfaceFieldScene() {
    d_->renderer->RemoveActor(d_->actor);
    d_->renderer->RemoveActor2D(d_->bar);
}

void SurfaceFieldScene::setField(const std::vector<Piece>& pieces, const std::string& title) {
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> tris;
    vtkNew<vtkDoubleArray> values;
    values->SetName("field");
    double largest = 0;
    for (const Piece& piece : pieces) {
        const vtkIdType first = pts->GetNumberOfPoints();
        const std::size_t n = piece.points.size() / 3;
        if (piece.values.size() != n) continue;
        for (std::size_t k = 0; k < n; ++k) {
            pts->InsertNextPoint(piece.points[3 * k], piece.points[3 * k + 1], piece.points[3 * k + 2]);
            values->InsertNextValue(piece.values[k]);
            if (std::isfinite(piece.values[k])) largest = std::max(largest, std::abs(piece.values[k]));
        }
        for (std::size_t t = 0; t + 2 < piece.triangles.size(); t += 3) {
            const vtkIdType ids[3] = {first + piece.triangles[t], first + piece.triangles[t + 1], first + piece.triangles[t + 2]};
            tris->InsertNextCell(3, ids);
        }
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(pts);
    poly->SetPolys(tris);
    poly->GetPointData()->SetScalars(values);
    d_->mapper->SetInputData(poly);
    d_->points = static_cast<int>(pts->GetNumberOfPoints());
    d_->largest = largest;
    d_->title = title;
    const double m = largest > 0 ? largest : 1.0;
    d_->lut->SetRange(-m, m);
    d_->lut->Modified();
    d_->bar->SetTitle(title.c_str());
    d_->actor->SetVisibility(d_->points > 0);
    d_->bar->SetVisibility(d_->points > 0);
}

void SurfaceFieldScene::clear() {
    d_->mapper->SetInputData(vtkNew<vtkPolyData>());
    d_->points = 0;
    d_->largest = 0;
    d_->title.clear();
    d_->actor->SetVisibility(false);
    d_->bar->SetVisibility(false);
}

bool SurfaceFieldScene::shown() const {
    return d_->points > 0;
}

int SurfaceFieldScene::pointCount() const {
    return d_->points;
}

std::array<double, 2> SurfaceFieldScene::range() const {
    return {-d_->largest, d_->largest};
}

std::string SurfaceFieldScene::title() const {
    return d_->title;
}

}  // namespace aero::ui
