#include "FlowWorkspace.h"

#include <QLocale>
#include <QMessageBox>
#include <cmath>

#include "Document.h"
#include "FlowPanel.h"
#include "FlowRunner.h"
#include "FlowScene.h"
#include "ResidualPlot.h"
#include "SectionView.h"
#include "VtkViewport.h"
#include "common/Error.h"

namespace aero::ui {

namespace {

FlowPanel::Tone toneOf(FlowRunner::State s) {
    switch (s) {
        case FlowRunner::State::Running:
            return FlowPanel::Tone::Busy;
        case FlowRunner::State::Converged:
            return FlowPanel::Tone::Good;
        case FlowRunner::State::NotConverged:
        case FlowRunner::State::Stopped:
            return FlowPanel::Tone::Warning;
        case FlowRunner::State::Failed:
            return FlowPanel::Tone::Bad;
        case FlowRunner::State::None:
            break;
    }
    return FlowPanel::Tone::Neutral;
}

}  // namespace

FlowWorkspace::FlowWorkspace(Document* document, JobRunner* jobs, VtkViewport* viewport, FlowScene* scene,
                             QWidget* parentWidget, QObject* parent)
    : QObject(parent), document_(document), viewport_(viewport), scene_(scene), dialogParent_(parentWidget) {
    runner_ = new FlowRunner(document, jobs, this);
    panel_ = new FlowPanel(parentWidget);
    plot_ = new ResidualPlot(parentWidget);
    sections_ = new SectionView(parentWidget);

    // The case's options in the panel; the panel's edits as undoable edits of the case.
    auto showCase = [this] {
        panel_->setCase(document_->caseFile());
        panel_->setCanContinue(runner_->canContinue());
    };
    connect(document_, &Document::reset, this, showCase);
    connect(document_, &Document::flowOptionsChanged, this, showCase);
    connect(document_, &Document::meshOptionsChanged, this, showCase);
    connect(document_, &Document::titleChanged, this, showCase);  // a saved project can keep restarts
    showCase();
    connect(panel_, &FlowPanel::optionEdited, this,
            [this, showCase](const std::string& section, const std::string& key, const io::OptionValue& v) {
                try {
                    document_->setOption(section == "flow" ? Document::Section::Flow : Document::Section::Mesh, key, v);
                } catch (const aero::Error& e) {
                    showCase();
                    QMessageBox::critical(dialogParent_, tr("Cannot change the case"), QString::fromStdString(e.what()));
                }
            });

    // Running.
    connect(panel_, &FlowPanel::solveRequested, this, &FlowWorkspace::solve);
    connect(panel_, &FlowPanel::stopRequested, this, &FlowWorkspace::stop);
    connect(panel_, &FlowPanel::continueRequested, this, &FlowWorkspace::continueRun);
    connect(runner_, &FlowRunner::started, this, [this] {
        plot_->begin(document_->caseFile().flow.newton.relativeTolerance);
        panel_->setProgress({});
    });
    connect(runner_, &FlowRunner::reported, this, [this](const FlowRunProgress& p) {
        plot_->add(p);
        if (p.hasIteration && p.iteration.rejected.empty()) {
            const flow::FlowIteration& it = p.iteration;
            panel_->setProgress(tr("%1iteration %2: residual %3 of the start, CFL %4, %5 GMRES (%6), %7 s")
                                    .arg(p.coarse ? tr("Coarse grid, ") : QString())
                                    .arg(p.iterationOffset + it.iteration)
                                    .arg(QString::number(it.relativeResidual, 'e', 2))
                                    .arg(QLocale().toString(it.cfl, 'g', 3))
                                    .arg(it.linearIterations)
                                    .arg(it.exact ? tr("exact Jacobian") : tr("approximate Jacobian"))
                                    .arg(QLocale().toString(it.seconds, 'f', 1)));
        } else if (!p.hasIteration && !p.message.empty()) {
            QString s = QString::fromStdString(p.message);
            s[0] = s[0].toUpper();
            panel_->setProgress(s + QStringLiteral("..."));
        }
    });
    connect(runner_, &FlowRunner::stateChanged, this, &FlowWorkspace::onStateChanged);
    connect(runner_, &FlowRunner::resultChanged, this, &FlowWorkspace::onResultChanged);
    connect(runner_, &FlowRunner::outdatedChanged, this, &FlowWorkspace::showResult);
    connect(runner_, &FlowRunner::message, this, &FlowWorkspace::message);

    // Display.
    connect(panel_, &FlowPanel::fieldChanged, this, [this](FlowField f) {
        scene_->setField(f);
        applyRange();
    });
    connect(panel_, &FlowPanel::rangeChanged, this, [this] { applyRange(); });
    connect(panel_, &FlowPanel::contourCountChanged, this, [this](int n) {
        scene_->setContourCount(n > 0 ? n : scene_->contourCount());
        scene_->setPartVisible(FlowPart::Contours, n > 0);
        viewport_->requestRender();
    });
    connect(panel_, &FlowPanel::partToggled, this, [this](FlowPart part, bool on) {
        scene_->setPartVisible(part, on);
        viewport_->requestRender();
        if (part == FlowPart::Wall) emit solutionShownChanged(wallShown());
    });
    connect(panel_, &FlowPanel::sliceChanged, this, [this](int axis, double position) {
        scene_->setSlice(axis, position);
        viewport_->requestRender();
    });
    connect(sections_, &SectionView::stationsChanged, this, &FlowWorkspace::cutSections);
    connect(sections_, &SectionView::fillRequested, this, &FlowWorkspace::fillStations);
    scene_->setField(panel_->field());
    scene_->setSlice(panel_->sliceAxis(), panel_->slicePosition());
    onStateChanged();
}

void FlowWorkspace::solve() {
    QString error;
    if (!runner_->start(&error)) emit message(error, 8000);
}

void FlowWorkspace::stop() {
    runner_->stop();
}

void FlowWorkspace::continueRun() {
    QString error;
    if (!runner_->start(&error, true)) emit message(error, 8000);
}

bool FlowWorkspace::wallShown() const {
    return scene_->wallShown();
}

void FlowWorkspace::onStateChanged() {
    const FlowRunner::State s = runner_->state();
    panel_->setRunning(s == FlowRunner::State::Running);
    panel_->setCanContinue(runner_->canContinue());
    panel_->setStatus(s == FlowRunner::State::None ? tr("No solution yet.") : runner_->stateText(), toneOf(s));
}

void FlowWorkspace::onResultChanged() {
    const auto r = runner_->result();
    showResult();
    if (r && r->flow && sections_->stations().empty()) fillStations();
    else cutSections();
}

void FlowWorkspace::showResult() {
    const auto r = runner_->result();
    const bool current = r && !runner_->outdated();
    scene_->setResult(current ? r : nullptr);
    if (current) {
        panel_->setSliceBounds(scene_->gridBounds());
        scene_->setSlice(panel_->sliceAxis(), panel_->slicePosition());
    }
    panel_->setResult(r, runner_->outdated());
    applyRange();
    if (runner_->outdated())
        sections_->setCuts({}, tr("The solution is outdated: solve again to cut the current shape."));
    else
        cutSections();
    viewport_->requestRender();
    const bool shown = wallShown();
    if (shown != shown_ || current) {
        shown_ = shown;
        emit solutionShownChanged(shown);
    }
}

void FlowWorkspace::applyRange() {
    if (panel_->automaticRange()) {
        scene_->setRange(std::nullopt);
        panel_->setAutomaticRange(scene_->range());
    } else {
        scene_->setRange(panel_->chosenRange());
    }
    viewport_->requestRender();
}

void FlowWorkspace::cutSections() {
    if (scene_->empty()) {
        if (!runner_->outdated()) sections_->setCuts({}, {});
        return;
    }
    const std::vector<double> stations = sections_->stations();
    if (stations.empty()) {
        sections_->setCuts({}, tr("Type the stations (y) to cut, e.g. 0, 0.5, 1."));
        scene_->cutWall({}, FlowField::PressureCoefficient);
        viewport_->requestRender();
        return;
    }
    const std::vector<SectionCut> cuts = scene_->cutWall(stations, FlowField::PressureCoefficient);
    const auto b = scene_->wallBounds();
    int outside = 0;
    for (double y : stations) outside += (y < b[2] - 1e-9 || y > b[3] + 1e-9) ? 1 : 0;
    sections_->setCuts(cuts, outside > 0 ? tr("%1 of the stations lie outside the body's span [%2, %3].")
                                               .arg(outside)
                                               .arg(b[2], 0, 'g', 4)
                                               .arg(b[3], 0, 'g', 4)
                                         : QString());
    viewport_->requestRender();
}

void FlowWorkspace::fillStations() {
    if (scene_->empty()) return;
    const auto b = scene_->wallBounds();
    // From the root (the symmetry plane, or the body's side) across the span.
    const double from = b[2] <= 0 && b[3] > 0 ? 0.0 : b[2];
    sections_->fillStations(from, b[3]);
    cutSections();
}

}  // namespace aero::ui
