#include "SensitivityWorkspace.h"

#include <QAction>
#include <QLabel>
#include <QLocale>
#include <QStringList>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "ActionSet.h"
#include "DesignVariablePanel.h"
#include "Document.h"
#include "FlowRunner.h"
#include "JobRunner.h"  // SensitivityRunner.h's inline job() needs the complete Job
#include "LatticeScene.h"
#include "ModelTree.h"
#include "OptimizationWorkspace.h"
#include "OverlayScene.h"
#include "PatchScene.h"
#include "SensitivityRunner.h"
#include "SurfaceFieldScene.h"
#include "VtkViewport.h"
#include "ffd/Embedding.h"
#include "io/CaseFile.h"

namespace aero::ui {

namespace {

constexpr int kArrowSamples = 7;  // sensitivity arrows per patch and direction

/// The diagonal of axis-aligned bounds {xmin, xmax, ymin, ymax, zmin, zmax}.
double diagonal(const std::array<double, 6>& b) {
    return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
                     (b[5] - b[4]) * (b[5] - b[4]));
}

}  // namespace

SensitivityWorkspace::SensitivityWorkspace(Document* document, SensitivityRunner* runner,
                                           FlowRunner* flow, OptimizationWorkspace* optimization,
                                           const ActionSet& actions, const Views& views,
                                           QObject* parent)
    : QObject(parent),
      document_(document),
      runner_(runner),
      flow_(flow),
      optimization_(optimization),
      actions_(actions),
      views_(views) {
    const ActionSet& a = actions_;
    DesignVariablePanel* variables = views_.variables;
    connect(a.computeSensitivities, &QAction::triggered, this, &SensitivityWorkspace::compute);
    connect(variables, &DesignVariablePanel::computeGradientRequested, this,
            &SensitivityWorkspace::compute);
    connect(a.cancelSensitivities, &QAction::triggered, runner_, &SensitivityRunner::cancel);
    connect(a.confirmPrediction, &QAction::triggered, this, &SensitivityWorkspace::confirm);
    connect(variables, &DesignVariablePanel::confirmRequested, this,
            &SensitivityWorkspace::confirm);
    connect(runner_, &SensitivityRunner::message, this, &SensitivityWorkspace::message);
    connect(runner_, &SensitivityRunner::stateChanged, this, &SensitivityWorkspace::updateGradient);
    connect(runner_, &SensitivityRunner::resultChanged, this,
            &SensitivityWorkspace::updateGradient);
    connect(runner_, &SensitivityRunner::outdatedChanged, this,
            &SensitivityWorkspace::updateGradient);
    connect(runner_, &SensitivityRunner::predictionChanged, this,
            &SensitivityWorkspace::updatePrediction);
    connect(flow_, &FlowRunner::stateChanged, this, &SensitivityWorkspace::updatePrediction);
    connect(document_, &Document::latticesMoved, this, &SensitivityWorkspace::updateGradientArrows);
    connect(document_, &Document::structureChanged, this, &SensitivityWorkspace::updateGradient);
    connect(a.gradientArrows, &QAction::toggled, this, &SensitivityWorkspace::updateGradientArrows);
    // The objective: the case's optimization objective when it has one, or a force coefficient.
    connect(document_, &Document::reset, this, &SensitivityWorkspace::fillObjectives);
    connect(document_, &Document::optimizationOptionsChanged, this,
            &SensitivityWorkspace::fillObjectives);
    connect(variables, &DesignVariablePanel::objectiveChosen, this,
            &SensitivityWorkspace::chooseObjective);
    fillObjectives();
    connect(a.surfaceSensitivity, &QAction::toggled, this,
            &SensitivityWorkspace::updateSurfaceSensitivity);
    connect(document_, &Document::shapeChanged, this, [this] {
        if (views_.surfaceField->shown()) updateSurfaceSensitivity();
    });
    connect(views_.tree, &ModelTree::patchVisibilityChanged, this,
            &SensitivityWorkspace::updateSurfaceSensitivity);
    connect(optimization_, &OptimizationWorkspace::viewShownChanged, this,
            &SensitivityWorkspace::updateSurfaceSensitivity);
    connect(a.lattices, &QAction::toggled, this, &SensitivityWorkspace::updateGradientArrows);
    connect(views_.tree, &ModelTree::latticeVisibilityChanged, this,
            &SensitivityWorkspace::updateGradientArrows);
    updateGradient();
}

void SensitivityWorkspace::compute() {
    QString error;
    if (!runner_->start(&error)) emit message(error, 8000);
}

void SensitivityWorkspace::confirm() {
    QString error;
    if (!runner_->confirm(&error)) emit message(error, 8000);
}

void SensitivityWorkspace::fillObjectives() {
    const io::CaseFile& c = document_->caseFile();
    QStringList items;
    if (c.optimization.present)
        items << tr("Case: %1 %2")
                     .arg(c.optimization.maximize ? tr("maximize") : tr("minimize"),
                          QString::fromStdString(c.optimization.objective));
    items << tr("Maximize CL/CD") << tr("Maximize CL") << tr("Minimize CD");
    runner_->setObjective(std::nullopt);  // a new project, or its objective changed
    views_.variables->setObjectiveChoices(items, 0);
}

void SensitivityWorkspace::chooseObjective(int index) {
    const int fixed = index - (document_->caseFile().optimization.present ? 1 : 0);
    static const Objective kFixed[] = {{"CL/CD", true}, {"CL", true}, {"CD", false}};
    runner_->setObjective(fixed >= 0 && fixed < 3 ? std::optional<Objective>(kFixed[fixed])
                                                  : std::nullopt);
    updateGradient();
}

void SensitivityWorkspace::updateShapeArrows() {
    DesignVariablePanel* variables = views_.variables;
    const PatchScene& scene = *views_.patches;
    const int var = variables->currentVariable();
    const ffd::FfdModel* model = document_->model();
    const bool on = actions_.sensitivity->isChecked();
    if (!on || !model || var < 0 || var >= model->design().size()) {
        views_.shapeArrows->clearArrows();
        variables->setSensitivityNote(on && model ? tr("Select a variable to see its arrows.")
                                                  : QString());
        return;
    }
    const geometry::PatchSet derivative = document_->shapeDerivative(var);
    std::vector<char> hidden(static_cast<std::size_t>(scene.patchCount()), 0);
    for (int p = 0; p < scene.patchCount(); ++p)
        hidden[static_cast<std::size_t>(p)] = scene.patchVisible(p) ? 0 : 1;
    std::vector<double> points, vectors;
    const double largest =
        sensitivityField(document_->shape(), derivative, kArrowSamples, hidden, points, vectors);
    const double length = 0.1 * diagonal(scene.bounds());
    views_.shapeArrows->setArrows(points, vectors, length);
    const QString name =
        QString::fromStdString(model->design().variables()[static_cast<std::size_t>(var)].name);
    variables->setSensitivityNote(
        largest > 0 ? tr("Arrows: dS/dv of %1; the longest is %2 (drawn %3 long).")
                          .arg(name)
                          .arg(largest, 0, 'g', 3)
                          .arg(length, 0, 'g', 2)
                    : tr("%1 does not move the surface.").arg(name));
}

void SensitivityWorkspace::updateGradient() {
    const auto r = runner_->result();
    if (!r) {
        QString note;
        if (runner_->state() == SensitivityRunner::State::Running)
            note = tr("Computing the gradient of %1...")
                       .arg(QString::fromStdString(runner_->objective().name));
        else if (runner_->state() == SensitivityRunner::State::Failed)
            note = tr("No gradient: %1").arg(runner_->reason());
        views_.variables->clearGradient(note);
    } else {
        const QString name = QString::fromStdString(r->objective.name);
        const QString sense = r->objective.maximize ? tr("maximized") : tr("minimized");
        QString note = runner_->outdated()
                           ? tr("d%1/dv at an earlier design (%1 = %2, %3): the design changed "
                                "since; compute again "
                                "for the design as shown.")
                                 .arg(name, QLocale().toString(r->J, 'g', 5), sense)
                           : tr("d%1/dv of the design as shown (%1 = %2, %3); green arrows at the "
                                "lattice points show "
                                "which way improves it.")
                                 .arg(name, QLocale().toString(r->J, 'g', 5), sense);
        if (runner_->state() == SensitivityRunner::State::Running)
            note += tr(" Computing again...");
        views_.variables->setGradient(r->dv, name, !runner_->outdated(), note);
    }
    updateGradientArrows();
    updateSurfaceSensitivity();
    updatePrediction();
}

void SensitivityWorkspace::updateSurfaceSensitivity() {
    const auto r = runner_->result();
    const ffd::FfdModel* model = document_->model();
    const PatchScene& scene = *views_.patches;
    if (!r || !model || !actions_.surfaceSensitivity->isChecked() || optimization_->viewShown() ||
        r->dUnique.size() != 3 * static_cast<std::size_t>(model->index().uniqueCount()) ||
        document_->baseline().size() != scene.patchCount()) {
        views_.surfaceField->clear();
        views_.viewport->requestRender();
        return;
    }
    // dJ/dA as the control points of the baseline's nets (knots and weights), sampled where the
    // wall is drawn, along the drawn wall's outward normals.
    geometry::PatchSet nets = document_->baseline();
    ffd::scatter(model->index(), r->dUnique, nets);
    const auto b = scene.bounds();
    const std::array<double, 3> centre{(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2};
    std::vector<SurfaceFieldScene::Piece> pieces;
    for (int p = 0; p < scene.patchCount(); ++p) {
        if (!scene.patchVisible(p)) continue;
        PatchScene::SurfaceMesh mesh = scene.surfaceMesh(p);
        SurfaceFieldScene::Piece piece;
        const std::vector<double> normals = outwardNormals(mesh.points, mesh.triangles, centre);
        piece.values =
            normalSensitivity(nets.patches[static_cast<std::size_t>(p)], mesh.uv, normals);
        piece.points = std::move(mesh.points);
        piece.triangles = std::move(mesh.triangles);
        pieces.push_back(std::move(piece));
    }
    const std::string name = r->objective.name;
    views_.surfaceField->setField(pieces, "d" + name + "/dA \u00b7 n\n(n outward)");
    views_.viewport->requestRender();
}

void SensitivityWorkspace::updateGradientArrows() {
    const auto r = runner_->result();
    const auto& moved = document_->lattices();
    if (!r || !actions_.gradientArrows->isChecked() || !actions_.lattices->isChecked() ||
        optimization_->viewShown() || r->dLattice.size() != moved.size()) {
        views_.gradientArrows->clearArrows();
        views_.viewport->requestRender();
        return;
    }
    // At the lattice points as shown, towards a better objective.
    const double sign = r->objective.maximize ? 1.0 : -1.0;
    std::vector<double> points, vectors;
    for (std::size_t l = 0; l < moved.size(); ++l) {
        if (!views_.lattices->latticeVisible(static_cast<int>(l)) ||
            r->dLattice[l].size() != moved[l].points.size())
            continue;
        points.insert(points.end(), moved[l].points.begin(), moved[l].points.end());
        for (double g : r->dLattice[l]) vectors.push_back(sign * g);
    }
    views_.gradientArrows->setArrows(points, vectors, 0.1 * diagonal(views_.patches->bounds()));
    views_.viewport->requestRender();
}

void SensitivityWorkspace::updatePrediction() {
    const QString text = runner_->predictionText();
    const bool flowBusy = flow_->running();
    views_.variables->setPrediction(text, !flowBusy);
    views_.prediction->setText(text);
    views_.prediction->setVisible(!text.isEmpty());
    actions_.confirmPrediction->setEnabled(runner_->result() != nullptr && !flowBusy);
}

}  // namespace aero::ui
