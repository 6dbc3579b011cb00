#include "OptimizationScene.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "FlowScene.h"
#include "LatticeScene.h"
#include "nurbs/Surface.h"

namespace aero::ui {

namespace {

constexpr int kSamples = 17;  // per patch and direction: a shape for display, not for analysis

// The patches sampled on a kSamples x kSamples grid each, as quads.
vtkSmartPointer<vtkPolyData> sampledShape(const geometry::PatchSet& set) {
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> quads;
    std::vector<double> us(kSamples), vs(kSamples), xyz(3 * kSamples * kSamples);
    for (const geometry::Patch& p : set.patches) {
        if (p.knotsU.empty() || p.knotsV.empty()) continue;
        const double u0 = p.knotsU[static_cast<std::size_t>(p.degreeU)],
                     u1 = p.knotsU[static_cast<std::size_t>(p.countU)];
        const double v0 = p.knotsV[static_cast<std::size_t>(p.degreeV)],
                     v1 = p.knotsV[static_cast<std::size_t>(p.countV)];
        for (int i = 0; i < kSamples; ++i) {
            const double t = static_cast<double>(i) / (kSamples - 1);
            us[static_cast<std::size_t>(i)] = u0 + t * (u1 - u0);
            vs[static_cast<std::size_t>(i)] = v0 + t * (v1 - v0);
        }
        nurbs::sampleGrid(p, us, vs, xyz.data());
        const vtkIdType base = points->GetNumberOfPoints();
        for (int k = 0; k < kSamples * kSamples; ++k)
            points->InsertNextPoint(&xyz[3 * static_cast<std::size_t>(k)]);
        for (int j = 0; j + 1 < kSamples; ++j)
            for (int i = 0; i + 1 < kSamples; ++i) {
                const vtkIdType a = base + i + static_cast<vtkIdType>(kSamples) * j;
                const vtkIdType ids[4] = {a, a + 1, a + 1 + kSamples, a + kSamples};
                quads->InsertNextCell(4, ids);
            }
    }
    auto poly = vtkSmartPointer<vtkPolyData>::New();
    poly->SetPoints(points);
    poly->SetPolys(quads);
    return poly;
}

// A shape drawn as one surface of one colour.
struct ShapeActor {
    vtkNew<vtkPolyDataNormals> normals;
    vtkNew<vtkPolyDataMapper> mapper;
    vtkNew<vtkActor> actor;

    ShapeActor(vtkRenderer* renderer, double r, double g, double b) {
        normals->ComputePointNormalsOn();
        normals->SplittingOff();
        normals->ConsistencyOn();
        normals->SetInputData(vtkNew<vtkPolyData>());
        mapper->SetInputConnection(normals->GetOutputPort());
        mapper->ScalarVisibilityOff();
        actor->SetMapper(mapper);
        actor->GetProperty()->SetColor(r, g, b);
        actor->GetProperty()->SetAmbient(0.3);
        actor->GetProperty()->SetDiffuse(0.75);
        actor->GetProperty()->SetSpecular(0.1);
        actor->PickableOff();
        actor->SetVisibility(false);
        renderer->AddActor(actor);
    }
    const geometry::PatchSet* current = nullptr;  // what the polydata was sampled from
    void set(const geometry::PatchSet* shape) {
        if (shape == current) return;
        current = shape;
        normals->SetInputData(shape ? sampledShape(*shape) : vtkSmartPointer<vtkPolyData>::New());
    }
};

}  // namespace

struct OptimizationScene::Impl {
    vtkSmartPointer<vtkRenderer> renderer;
    std::unique_ptr<FlowScene> flow, compareFlow;
    std::unique_ptr<LatticeScene> lattices;
    std::unique_ptr<ShapeActor> shape, compareShape;
    vtkNew<vtkTextActor> caption;
    std::shared_ptr<const EvaluationSnapshot> shown, compared;
    CompareMode mode = CompareMode::Off;
    bool visible = false;
    bool latticesVisible = true;
    std::array<double, 3> offset{0, 0, 0};

    bool shownHasFlow() const {
        return shown && shown->flow && shown->flow->flow && !shown->flow->fields[0].empty();
    }
    bool comparedHasFlow() const {
        return compared && compared->flow && compared->flow->flow &&
               !compared->flow->fields[0].empty();
    }

    // Bounds of a snapshot's geometry (its control points: they contain the surfaces).
    static std::array<double, 6> bounds(const EvaluationSnapshot& s) {
        std::array<double, 6> b{};
        for (int k = 0; k < 3; ++k) {
            b[static_cast<std::size_t>(2 * k)] = std::numeric_limits<double>::infinity();
            b[static_cast<std::size_t>(2 * k + 1)] = -std::numeric_limits<double>::infinity();
        }
        for (const geometry::Patch& p : s.shape.patches)
            for (std::size_t i = 0; i + 2 < p.points.size(); i += 3)
                for (std::size_t k = 0; k < 3; ++k) {
                    b[2 * k] = std::min(b[2 * k], p.points[i + k]);
                    b[2 * k + 1] = std::max(b[2 * k + 1], p.points[i + k]);
                }
        if (!(b[0] <= b[1])) b = {0, 0, 0, 0, 0, 0};
        return b;
    }

    void update() {
        // The shown evaluation: its flow if kept, else its shape.
        const bool flowOn = visible && shownHasFlow();
        const std::shared_ptr<const FlowRunResult> wanted = flowOn ? shown->flow : nullptr;
        if (flow->result() != wanted.get()) flow->setResult(wanted);
        flow->setShown(visible);
        shape->set(visible && shown && !flowOn ? &shown->shape : nullptr);
        shape->actor->SetVisibility(visible && shown && !flowOn);

        std::vector<LatticeView> views;
        if (visible && shown) {
            for (std::size_t l = 0; l < shown->lattices.size(); ++l) {
                LatticeView v;
                v.lattice = shown->lattices[l];
                if (l < shown->injectivity.size()) {
                    v.injective = shown->injectivity[l].injective;
                    v.foldAt = shown->injectivity[l].minPoint;
                }
                views.push_back(std::move(v));
            }
        }
        lattices->setLattices(std::move(views));
        lattices->setVisible(visible && latticesVisible);

        // The compared evaluation.
        offset = {0, 0, 0};
        const bool compareOn = visible && compared && mode != CompareMode::Off;
        if (compareOn && mode == CompareMode::SideBySide && shown) {
            // Above it: the views look at the symmetry plane (Y = 0), so a shift along Y would
            // hide one behind the other.
            const auto a = bounds(*shown), b = bounds(*compared);
            const double span = std::max(a[5] - a[4], b[5] - b[4]);
            offset = {0, 0, a[5] - b[4] + 0.25 * span};
        }
        const bool compareFlowOn =
            compareOn && mode == CompareMode::SideBySide && comparedHasFlow();
        const std::shared_ptr<const FlowRunResult> other = compareFlowOn ? compared->flow : nullptr;
        if (compareFlow->result() != other.get()) compareFlow->setResult(other);
        compareFlow->setShown(compareFlowOn);
        compareFlow->setOffset(offset);
        compareFlow->setField(flow->field());
        if (compareFlowOn) compareFlow->setRange(flow->range());  // one colour scale for both
        compareShape->set(compareOn && !compareFlowOn ? &compared->shape : nullptr);
        compareShape->actor->SetVisibility(compareOn && !compareFlowOn);
        compareShape->actor->SetPosition(offset[0], offset[1], offset[2]);
        vtkProperty* p = compareShape->actor->GetProperty();
        if (mode == CompareMode::Overlay) {
            p->SetColor(0.95, 0.55, 0.15);
            p->SetOpacity(0.35);
        } else {
            p->SetColor(0.78, 0.80, 0.84);
            p->SetOpacity(1.0);
        }
        caption->SetVisibility(visible && shown);
    }
};

OptimizationScene::OptimizationScene(vtkRenderer* renderer) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.renderer = renderer;
    d.flow = std::make_unique<FlowScene>(renderer);
    d.compareFlow = std::make_unique<FlowScene>(renderer);
    d.compareFlow->setColourBarShown(false);
    // Its wall only: its symmetry plane would lie in the shown one's (or in front of it).
    d.compareFlow->setPartVisible(FlowPart::Symmetry, false);
    d.compareFlow->setPartVisible(FlowPart::Slice, false);
    d.compareFlow->setPartVisible(FlowPart::Contours, false);
    d.lattices = std::make_unique<LatticeScene>(renderer);
    d.shape = std::make_unique<ShapeActor>(renderer, 0.70, 0.76, 0.86);
    d.compareShape = std::make_unique<ShapeActor>(renderer, 0.95, 0.55, 0.15);
    vtkTextProperty* t = d.caption->GetTextProperty();
    t->SetFontSize(15);
    t->SetColor(0.12, 0.12, 0.16);
    t->ShadowOff();
    t->BoldOn();
    d.caption->SetPosition(12, 12);
    d.caption->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    d.caption->GetPositionCoordinate()->SetValue(0.015, 0.93);
    t->SetVerticalJustificationToTop();
    d.caption->SetVisibility(false);
    renderer->AddActor2D(d.caption);
    d.update();
}

OptimizationScene::~OptimizationScene() {
    Impl& d = *d_;
    d.renderer->RemoveActor(d.shape->actor);
    d.renderer->RemoveActor(d.compareShape->actor);
    d.renderer->RemoveActor2D(d.caption);
}

void OptimizationScene::setShown(std::shared_ptr<const EvaluationSnapshot> evaluation) {
    d_->shown = std::move(evaluation);
    d_->update();
}

const EvaluationSnapshot* OptimizationScene::shown() const {
    return d_->shown.get();
}

void OptimizationScene::setCompared(std::shared_ptr<const EvaluationSnapshot> evaluation,
                                    CompareMode mode) {
    d_->compared = std::move(evaluation);
    d_->mode = mode;
    d_->update();
}

const EvaluationSnapshot* OptimizationScene::compared() const {
    return d_->mode == CompareMode::Off ? nullptr : d_->compared.get();
}

CompareMode OptimizationScene::compareMode() const {
    return d_->mode;
}

void OptimizationScene::setCaption(const std::string& text) {
    d_->caption->SetInput(text.c_str());
}

std::string OptimizationScene::caption() const {
    const char* s = d_->caption->GetInput();
    return s ? s : "";
}

void OptimizationScene::setVisible(bool visible) {
    if (visible == d_->visible) return;
    d_->visible = visible;
    d_->update();
}

bool OptimizationScene::visible() const {
    return d_->visible;
}

void OptimizationScene::setLatticesVisible(bool visible) {
    d_->latticesVisible = visible;
    d_->lattices->setVisible(d_->visible && visible);
}

bool OptimizationScene::latticesVisible() const {
    return d_->latticesVisible;
}

void OptimizationScene::setField(FlowField field) {
    d_->flow->setField(field);
    d_->compareFlow->setField(field);
    if (!d_->compareFlow->empty()) d_->compareFlow->setRange(d_->flow->range());
}

FlowField OptimizationScene::field() const {
    return d_->flow->field();
}

FlowScene& OptimizationScene::flow() {
    return *d_->flow;
}

bool OptimizationScene::flowDrawn() const {
    return d_->visible && !d_->flow->empty();
}

bool OptimizationScene::drawn() const {
    return d_->visible && d_->shown != nullptr;
}

std::array<double, 3> OptimizationScene::compareOffset() const {
    return d_->offset;
}

std::vector<double> OptimizationScene::viewPoints() const {
    std::vector<double> out;
    if (!drawn()) return out;
    out = d_->lattices->allPoints();
    auto corners = [&out](const std::array<double, 6>& b, const std::array<double, 3>& o) {
        for (int i = 0; i < 8; ++i) {
            out.push_back(b[static_cast<std::size_t>((i & 1) ? 1 : 0)] + o[0]);
            out.push_back(b[static_cast<std::size_t>((i & 2) ? 3 : 2)] + o[1]);
            out.push_back(b[static_cast<std::size_t>((i & 4) ? 5 : 4)] + o[2]);
        }
    };
    corners(Impl::bounds(*d_->shown), {0, 0, 0});
    if (d_->compared && d_->mode != CompareMode::Off)
        corners(Impl::bounds(*d_->compared), d_->offset);
    return out;
}

}  // namespace aero::ui
