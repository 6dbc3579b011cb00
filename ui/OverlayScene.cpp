#include "OverlayScene.h"

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3D.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <cmath>

#include "nurbs/Surface.h"

namespace aero::ui {

double sensitivityField(const geometry::PatchSet& shape, const geometry::PatchSet& derivative, int samples,
                        const std::vector<char>& hidden, std::vector<double>& points, std::vector<double>& vectors) {
    points.clear();
    vectors.clear();
    if (shape.size() != derivative.size() || samples < 2) return 0;
    double largest = 0;
    std::vector<double> x, v;
    for (int p = 0; p < shape.size(); ++p) {
        if (p < static_cast<int>(hidden.size()) && hidden[static_cast<std::size_t>(p)]) continue;
        const geometry::Patch& s = shape.patches[static_cast<std::size_t>(p)];
        const geometry::Patch& ds = derivative.patches[static_cast<std::size_t>(p)];
        std::vector<double> us(static_cast<std::size_t>(samples)), vs(static_cast<std::size_t>(samples));
        const double u0 = s.knotsU[static_cast<std::size_t>(s.degreeU)], u1 = s.knotsU[static_cast<std::size_t>(s.countU)];
        const double v0 = s.knotsV[static_cast<std::size_t>(s.degreeV)], v1 = s.knotsV[static_cast<std::size_t>(s.countV)];
        for (int i = 0; i < samples; ++i) {
            const double t = static_cast<double>(i) / (samples - 1);
            us[static_cast<std::size_t>(i)] = u0 + t * (u1 - u0);
            vs[static_cast<std::size_t>(i)] = v0 + t * (v1 - v0);
        }
        x.resize(3 * us.size() * vs.size());
        v.resize(x.size());
        nurbs::sampleGrid(s, us, vs, x.data());
        // S is linear in its control points (weights fixed): sampling the patch whose control
        // points are dA/dv gives dS/dv.
        nurbs::sampleGrid(ds, us, vs, v.data());
        points.insert(points.end(), x.begin(), x.end());
        vectors.insert(vectors.end(), v.begin(), v.end());
        for (std::size_t k = 0; k < v.size(); k += 3)
            largest = std::max(largest, std::sqrt(v[k] * v[k] + v[k + 1] * v[k + 1] + v[k + 2] * v[k + 2]));
    }
    return largest;
}

struct OverlayScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    vtkNew<vtkPolyDataMapper> failedMapper, arrowMapper;
    vtkNew<vtkActor> failed, arrows;
    vtkNew<vtkArrowSource> arrowSource;
    vtkNew<vtkGlyph3D> glyphs;
    int failedCount = 0;
    int arrowCount = 0;
};

OverlayScene::OverlayScene(vtkRenderer* renderer, const std::array<double, 3>& arrowColour) : d_(std::make_unique<Impl>()) {
    d_->renderer = renderer;
    d_->failedMapper->ScalarVisibilityOff();
    d_->failed->SetMapper(d_->failedMapper);
    vtkProperty* fp = d_->failed->GetProperty();
    fp->SetColor(0.85, 0.10, 0.75);
    fp->SetPointSize(13.0f);
    fp->RenderPointsAsSpheresOn();
    fp->LightingOff();
    d_->failed->PickableOff();

    d_->arrowSource->SetTipResolution(12);
    d_->arrowSource->SetShaftResolution(8);
    d_->arrowSource->SetTipLength(0.3);
    d_->arrowSource->SetTipRadius(0.09);
    d_->arrowSource->SetShaftRadius(0.03);
    d_->glyphs->SetSourceConnection(d_->arrowSource->GetOutputPort());
    d_->glyphs->SetVectorModeToUseVector();
    d_->glyphs->SetScaleModeToScaleByVector();
    d_->glyphs->OrientOn();
    d_->arrowMapper->SetInputConnection(d_->glyphs->GetOutputPort());
    d_->arrowMapper->ScalarVisibilityOff();
    d_->arrows->SetMapper(d_->arrowMapper);
    vtkProperty* ap = d_->arrows->GetProperty();
    ap->SetColor(arrowColour[0], arrowColour[1], arrowColour[2]);
    ap->SetAmbient(0.25);
    ap->SetDiffuse(0.8);
    d_->arrows->PickableOff();

    setFailedPoints({});
    clearArrows();
    renderer->AddActor(d_->failed);
    renderer->AddActor(d_->arrows);
}

OverlayScene::~OverlayScene() {
    d_->renderer->RemoveActor(d_->failed);
    d_->renderer->RemoveActor(d_->arrows);
}

void OverlayScene::setFailedPoints(const std::vector<double>& points) {
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> verts;
    for (std::size_t i = 0; i + 2 < points.size(); i += 3) {
        const vtkIdType id = pts->InsertNextPoint(points[i], points[i + 1], points[i + 2]);
        verts->InsertNextCell(1, &id);
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(pts);
    poly->SetVerts(verts);
    d_->failedMapper->SetInputData(poly);
    d_->failedCount = static_cast<int>(points.size() / 3);
    d_->failed->SetVisibility(d_->failedCount > 0);
}

int OverlayScene::failedPointCount() const {
    return d_->failedCount;
}

void OverlayScene::setArrows(const std::vector<double>& points, const std::vector<double>& vectors, double length) {
    double largest = 0;
    for (std::size_t k = 0; k + 2 < vectors.size(); k += 3)
        largest = std::max(largest, std::sqrt(vectors[k] * vectors[k] + vectors[k + 1] * vectors[k + 1] +
                                              vectors[k + 2] * vectors[k + 2]));
    if (!(largest > 0) || points.size() != vectors.size()) {
        clearArrows();
        return;
    }
    vtkNew<vtkPoints> pts;
    vtkNew<vtkDoubleArray> vec;
    vec->SetName("dSdv");
    vec->SetNumberOfComponents(3);
    for (std::size_t k = 0; k + 2 < vectors.size(); k += 3) {
        const double n = std::sqrt(vectors[k] * vectors[k] + vectors[k + 1] * vectors[k + 1] + vectors[k + 2] * vectors[k + 2]);
        if (n < 1e-3 * largest) continue;
        pts->InsertNextPoint(points[k], points[k + 1], points[k + 2]);
        vec->InsertNextTuple(&vectors[k]);
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(pts);
    poly->GetPointData()->SetVectors(vec);
    d_->glyphs->SetInputData(poly);
    d_->glyphs->SetScaleFactor(length / largest);
    d_->arrowCount = static_cast<int>(pts->GetNumberOfPoints());
    d_->arrows->SetVisibility(d_->arrowCount > 0);
}

void OverlayScene::clearArrows() {
    d_->glyphs->SetInputData(vtkSmartPointer<vtkPolyData>::New());
    d_->arrowCount = 0;
    d_->arrows->SetVisibility(false);
}

int OverlayScene::arrowCount() const {
    return d_->arrowCount;
}

}  // namespace aero::ui
