#include "OptimizationWorkspace.h"

#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLocale>
#include <QMessageBox>
#include <QPushButton>
#include <cmath>
#include <cstdio>

#include "Document.h"
#include "FlowScene.h"
#include "OptimizationPanel.h"
#include "OptimizationPlots.h"
#include "OptimizationScene.h"
#include "ProjectFiles.h"
#include "ResidualPlot.h"
#include "VtkViewport.h"
#include "common/Error.h"
#include "ffd/FfdModel.h"
#include "study/GeometryFiles.h"

namespace aero::ui {

namespace {

using Kind = study::OptimizationRecord::Kind;
using State = OptimizationRunner::State;

QString num(double v, int digits = 6) {
    return std::isfinite(v) ? QLocale().toString(v, 'g', digits) : QStringLiteral("\u2013");
}

OptimizationPanel::Tone toneOf(const OptimizationRunner& r) {
    switch (r.state()) {
        case State::Running:
        case State::Pausing:
            return OptimizationPanel::Tone::Busy;
        case State::Paused:
        case State::Stopped:
        case State::Recorded:
            return OptimizationPanel::Tone::Warning;
        case State::Finished: {
            const auto o = r.outcome();
            if (o && (*o == optimize::Status::Converged || *o == optimize::Status::IterationLimit ||
                      *o == optimize::Status::EvaluationLimit))
                return OptimizationPanel::Tone::Good;
            return OptimizationPanel::Tone::Warning;
        }
        case State::Failed:
            return OptimizationPanel::Tone::Bad;
        case State::None:
            break;
    }
    return OptimizationPanel::Tone::Neutral;
}

// ASCII for the 3D view's caption (VTK's fonts lack most symbols).
std::string captionOf(const OptimizationHistory::Evaluation& e, const std::string& objective) {
    const study::OptimizationRecord& r = e.record;
    std::string s = "Evaluation " + std::to_string(r.index);
    char buf[160];
    if (r.ok) {
        std::snprintf(buf, sizeof buf, ": %s %.6g, CL %.4f, CD %.5f", objective.c_str(), r.J, r.CL,
                      r.CD);
        s += buf;
    } else {
        s += ": failed (" + r.status + ")";
    }
    if (!e.snapshot || !e.snapshot->flow) s += " - shape only";
    return s;
}

}  // namespace

OptimizationWorkspace::OptimizationWorkspace(Document* document, JobRunner* jobs,
                                             VtkViewport* viewport, OptimizationScene* scene,
                                             QWidget* parentWidget, QObject* parent)
    : QObject(parent),
      document_(document),
      viewport_(viewport),
      scene_(scene),
      dialogParent_(parentWidget) {
    runner_ = new OptimizationRunner(document, jobs, this);
    panel_ = new OptimizationPanel(parentWidget);
    plots_ = new OptimizationPlots(parentWidget);

    // The case's problem in the panel; the panel's edits as undoable edits of the case.
    connect(document_, &Document::reset, this, &OptimizationWorkspace::showCase);
    connect(document_, &Document::optimizationOptionsChanged, this,
            &OptimizationWorkspace::showCase);
    connect(document_, &Document::flowOptionsChanged, this, &OptimizationWorkspace::showCase);
    connect(document_, &Document::titleChanged, this,
            &OptimizationWorkspace::showCase);  // the history's place
    connect(document_, &Document::structureChanged, this, &OptimizationWorkspace::showCase);
    connect(panel_, &OptimizationPanel::optionEdited, this,
            [this](const std::string& key, const io::OptionValue& v) {
                QString error;
                if (!ProjectFiles::guarded(
                        [&] { document_->setOption(Document::Section::Optimization, key, v); },
                        &error)) {
                    showCase();
                    QMessageBox::critical(dialogParent_, tr("Cannot change the optimization"),
                                          error);
                }
            });
    connect(panel_, &OptimizationPanel::startDesignChooseRequested, this,
            &OptimizationWorkspace::chooseStartDesign);
    connect(panel_, &OptimizationPanel::startDesignEdited, this, [this](const QString& path) {
        QString error;
        if (!setStartDesign(path, &error))
            QMessageBox::critical(dialogParent_, tr("Cannot start from this design"), error);
    });
    connect(panel_, &OptimizationPanel::volumeEdited, this, [this](std::optional<double> minimum) {
        QString error;
        if (!ProjectFiles::guarded([&] { document_->setMinVolume(minimum); }, &error)) {
            showCase();
            QMessageBox::critical(dialogParent_, tr("Cannot change the volume constraint"), error);
        }
    });

    // Running.
    connect(panel_, &OptimizationPanel::startRequested, this, &OptimizationWorkspace::start);
    connect(panel_, &OptimizationPanel::startOverRequested, this,
            &OptimizationWorkspace::startOver);
    connect(panel_, &OptimizationPanel::pauseRequested, this, &OptimizationWorkspace::pause);
    connect(panel_, &OptimizationPanel::stopRequested, this, &OptimizationWorkspace::stop);
    connect(panel_, &OptimizationPanel::resumeRequested, this, &OptimizationWorkspace::resume);
    connect(runner_, &OptimizationRunner::started, this, [this](bool resumed) {
        newSolve_ = true;
        plots_->residualPlot()->begin(document_->caseFile().flow.newton.relativeTolerance);
        plots_->residualPlot()->setTitle(tr("Flow residual"));
        if (!resumed) panel_->clearLog();
        panel_->setFollow(true);
        setViewShown(true);
    });
    connect(runner_, &OptimizationRunner::stateChanged, this,
            &OptimizationWorkspace::onStateChanged);
    connect(runner_, &OptimizationRunner::recordAdded, this, &OptimizationWorkspace::onRecord);
    connect(runner_, &OptimizationRunner::historyReset, this,
            &OptimizationWorkspace::onHistoryReset);
    connect(runner_, &OptimizationRunner::snapshotChanged, this, [this](int index) {
        if (index == shown_ || index == compared_) showEvaluation(shown_);
    });
    connect(runner_, &OptimizationRunner::flowReported, this, &OptimizationWorkspace::onFlowReport);
    connect(runner_, &OptimizationRunner::logged, panel_, &OptimizationPanel::appendLog);
    connect(runner_, &OptimizationRunner::message, this, &OptimizationWorkspace::message);

    // The evaluation shown.
    connect(panel_, &OptimizationPanel::evaluationChosen, this, [this](int index) {
        showEvaluation(index);
        if (index > 0) setViewShown(true);
    });
    connect(panel_, &OptimizationPanel::followToggled, this, [this](bool on) {
        if (on) showEvaluation(runner_->history().evaluationCount());
    });
    connect(panel_, &OptimizationPanel::viewToggled, this, &OptimizationWorkspace::setViewShown);
    connect(panel_, &OptimizationPanel::compareChanged, this, &OptimizationWorkspace::compareWith);
    connect(panel_, &OptimizationPanel::fieldChanged, this, [this](FlowField f) {
        scene_->setField(f);
        viewport_->requestRender();
    });
    connect(panel_, &OptimizationPanel::useDesignRequested, this, [this] {
        QString error;
        if (!useShownDesign(&error))
            QMessageBox::critical(dialogParent_, tr("Cannot use the design"), error);
    });
    connect(panel_, &OptimizationPanel::solveFlowRequested, this, [this] {
        QString error;
        if (!runner_->solveEvaluationFlow(shown_, &error)) emit message(error, 8000);
    });
    connect(panel_, &OptimizationPanel::exportShapeRequested, this,
            &OptimizationWorkspace::chooseAndExportShape);
    connect(panel_, &OptimizationPanel::exportHistoryRequested, this,
            &OptimizationWorkspace::chooseAndExportHistory);
    connect(panel_, &OptimizationPanel::exportPlotsRequested, this,
            &OptimizationWorkspace::chooseAndExportPlots);
    scene_->setField(panel_->field());
    showCase();
    onStateChanged();
    updateEvaluationPanel();
}

// ---- The problem
// ------------------------------------------------------------------------------------

void OptimizationWorkspace::showCase() {
    panel_->setCase(document_->caseFile(), runner_->historyPath());
    plots_->setProblem(document_->caseFile());
    onStateChanged();  // a saved project may have a history to resume
    updateSensitivities();
}

bool OptimizationWorkspace::setStartDesign(const QString& path, QString* error) {
    const std::string stored =
        path.isEmpty() ? std::string() : QFile::encodeName(QFileInfo(path).absoluteFilePath()).toStdString();
    QString why;
    if (ProjectFiles::guarded([&] { document_->setStartDesign(stored); }, &why)) return true;
    showCase();
    if (error) *error = why;
    return false;
}

void OptimizationWorkspace::chooseStartDesign() {
    const QString current = QString::fromStdString(document_->caseFile().optimization.startDesign);
    const QString history = runner_->historyPath();
    const QString dir = !current.isEmpty()   ? QFileInfo(current).dir().path()
                        : !history.isEmpty() ? QFileInfo(history).dir().path()
                                             : QDir::homePath();
    const QString path = QFileDialog::getOpenFileName(
        dialogParent_, tr("Start the Optimization from a Case's Design"), dir,
        tr("Case files (*.json)"));
    if (path.isEmpty()) return;
    QString error;
    if (!setStartDesign(path, &error))
        QMessageBox::critical(dialogParent_, tr("Cannot start from this design"), error);
}

// ---- Running
// ---------------------------------------------------------------------------------------

void OptimizationWorkspace::start() {
    if (runner_->historyExists()) {
        startOver();
        return;
    }
    QString error;
    if (!runner_->start(OptimizationRunner::Start::New, &error)) refuse(error);
}

void OptimizationWorkspace::startOver() {
    if (runner_->running()) return;
    if (runner_->historyExists()) {
        QMessageBox box(QMessageBox::Question, tr("Start Over"),
                        tr("Replace the optimization history %1?").arg(runner_->historyJsonlPath()),
                        QMessageBox::NoButton, dialogParent_);
        box.setObjectName(QStringLiteral("startOverQuestion"));
        box.setInformativeText(
            tr("A new run starts from the case's design and the %1 recorded evaluations are lost "
               "(Resume would continue them instead).")
                .arg(runner_->history().evaluationCount()));
        QPushButton* replace = box.addButton(tr("Replace and Start"), QMessageBox::AcceptRole);
        replace->setObjectName(QStringLiteral("replaceHistory"));
        QPushButton* keep = box.addButton(tr("Keep the History"), QMessageBox::RejectRole);
        box.setDefaultButton(keep);
        box.exec();
        if (box.clickedButton() != replace) return;
    }
    QString error;
    if (!runner_->start(OptimizationRunner::Start::Fresh, &error)) refuse(error);
}

void OptimizationWorkspace::pause() {
    runner_->pause();
}

void OptimizationWorkspace::stop() {
    runner_->stop();
}

void OptimizationWorkspace::resume() {
    QString error;
    if (!runner_->start(OptimizationRunner::Start::Resume, &error)) refuse(error);
}

void OptimizationWorkspace::refuse(const QString& why) {
    // Beside the button the user pressed, and in the status bar (until the state changes).
    onStateChanged();
    panel_->setRunState(why, OptimizationPanel::Tone::Bad, actions(), runner_->running());
    emit message(why, 10000);
}

OptimizationPanel::Actions OptimizationWorkspace::actions() const {
    const bool running = runner_->running();
    const bool busy = running || runner_->loading();
    const bool exists = runner_->historyExists();
    const bool geometry = document_->hasGeometry();
    OptimizationPanel::Actions can;
    can.start = geometry && !busy && !exists;
    can.startOver = geometry && !busy && exists;
    can.pause = running && runner_->state() == State::Running;
    can.stop = running;
    can.resume = geometry && !busy && exists;
    return can;
}

void OptimizationWorkspace::onStateChanged() {
    const State s = runner_->state();
    const bool exists = runner_->historyExists();
    QString text = runner_->stateText();
    if (s == State::None) {
        text = exists ? tr("A history exists: Resume continues it, Start Over replaces it.")
               : document_->caseFile().optimization.present
                   ? tr("Not run yet.")
                   : tr("Set up the problem below, then Start.");
        if (runner_->loading()) text = tr("Reading the history...");
    }
    panel_->setRunState(text, toneOf(*runner_), actions(), runner_->running());
    updateEvaluationPanel();
}

void OptimizationWorkspace::onHistoryReset() {
    plots_->setHistory(runner_->history());
    panel_->setEvaluationCount(runner_->history().evaluationCount());
    compared_ = 0;
    panel_->setComparedEvaluation(0);
    showEvaluation(runner_->history().evaluationCount());
    updateSensitivities();
    if (runner_->history().evaluationCount() > 0 && runner_->state() == State::Recorded)
        setViewShown(true);
}

void OptimizationWorkspace::onRecord(const study::OptimizationRecord& r) {
    const OptimizationHistory& h = runner_->history();
    if (r.kind == Kind::Values || r.kind == Kind::Gradient) newSolve_ = true;
    if (r.kind == Kind::Gradient) updateSensitivities();
    if (r.kind == Kind::Header || r.kind == Kind::Gradient) return;
    plots_->setHistory(h);
    if (r.kind != Kind::Values) return;
    panel_->setEvaluationCount(h.evaluationCount());
    if (panel_->follow() || shown_ == 0 || shown_ > h.evaluationCount()) {
        showEvaluation(h.evaluationCount());
    } else if (shown_ == r.index) {
        showEvaluation(shown_);  // replaced (replayed)
    } else {
        plots_->setShown(shown_, compared_);
    }
}

void OptimizationWorkspace::onFlowReport(const FlowRunProgress& p) {
    if (p.hasIteration) {
        if (newSolve_) {
            newSolve_ = false;
            plots_->residualPlot()->begin(document_->caseFile().flow.newton.relativeTolerance);
            const int k = runner_->running() ? runner_->currentEvaluation() : shown_;
            plots_->residualPlot()->setTitle(tr("Residual, eval. %1").arg(k));
        }
        plots_->residualPlot()->add(p);
        if (p.iteration.rejected.empty())
            panel_->setProgress(tr("Evaluation %1: flow iteration %2, residual %3 of the start")
                                    .arg(runner_->currentEvaluation())
                                    .arg(p.iterationOffset + p.iteration.iteration)
                                    .arg(QString::number(p.iteration.relativeResidual, 'e', 2)));
    } else if (!p.message.empty()) {
        QString s = QString::fromStdString(p.message);
        s[0] = s[0].toUpper();
        if (runner_->running())
            panel_->setProgress(
                tr("Evaluation %1: %2...").arg(runner_->currentEvaluation()).arg(s));
    }
}

// ---- The evaluation shown
// -----------------------------------------------------------------------------

void OptimizationWorkspace::showEvaluation(int index) {
    const OptimizationHistory& h = runner_->history();
    if (index < 0 || index > h.evaluationCount()) index = h.evaluationCount();
    shown_ = index;
    panel_->setCurrentEvaluation(index);
    const OptimizationHistory::Evaluation* e = h.evaluation(index);
    scene_->setShown(e ? e->snapshot : nullptr);
    applyCompare();
    plots_->setShown(shown_, compared_);
    updateEvaluationPanel();
    applyView();  // the first evaluation to show takes the view the run asked for
    viewport_->requestRender();
}

void OptimizationWorkspace::compareWith(int index, CompareMode mode) {
    compared_ = index;
    compareMode_ = mode;
    applyCompare();
    plots_->setShown(shown_, compared_);
    viewport_->requestRender();
}

void OptimizationWorkspace::applyCompare() {
    const OptimizationHistory::Evaluation* c = runner_->history().evaluation(compared_);
    const bool comparing = c && c->snapshot && compared_ != shown_;
    scene_->setCompared(comparing ? c->snapshot : nullptr, c ? compareMode_ : CompareMode::Off);
    // The caption names what is drawn: the shown evaluation, and the compared one and where.
    const std::string& objective = document_->caseFile().optimization.objective;
    const OptimizationHistory::Evaluation* e = runner_->history().evaluation(shown_);
    std::string caption = e ? captionOf(*e, objective) : std::string();
    if (e && comparing)
        caption += (compareMode_ == CompareMode::Overlay ? "\nOverlaid (orange): " : "\nAbove: ") +
                   captionOf(*c, objective);
    scene_->setCaption(caption);
}

bool OptimizationWorkspace::viewShown() const {
    return scene_->visible();
}

void OptimizationWorkspace::setViewShown(bool on) {
    viewWanted_ = on;
    panel_->setViewShown(on);
    applyView();
    viewport_->requestRender();
}

void OptimizationWorkspace::applyView() {
    // Only an evaluation takes the view: until the first one is recorded the project's design
    // (and its lattices) stay, rather than an empty view.
    const bool on = viewWanted_ && scene_->shown() != nullptr;
    scene_->setVisible(on);
    if (on != lastViewShown_) {
        lastViewShown_ = on;
        emit viewShownChanged(on);
    }
}

void OptimizationWorkspace::updateEvaluationPanel() {
    const OptimizationHistory& h = runner_->history();
    const OptimizationHistory::Evaluation* e = h.evaluation(shown_);
    if (!e) {
        panel_->setEvaluationText(h.evaluationCount() == 0 ? tr("No evaluations yet.") : QString(),
                                  false);
        panel_->setEvaluationActions(false, false, false);
        return;
    }
    const study::OptimizationRecord& r = e->record;
    const std::string& objective = document_->caseFile().optimization.objective;
    QString text;
    if (r.ok) {
        text = tr("%1 = %2;  CL %3, CD %4, L/D %5\nvolume %6, max. Mach %7, alpha %8\u00b0, %9 "
                  "flow iterations%10")
                   .arg(QString::fromStdString(objective), num(r.J, 8), num(r.CL, 6), num(r.CD, 6),
                        num(r.CD != 0 ? r.CL / r.CD : std::nan(""), 5), num(r.volume, 6),
                        num(r.maxMach, 4), num(r.alphaDeg, 4))
                   .arg(r.flowIterations)
                   .arg(r.replayed ? tr(" (replayed)") : QString());
    } else {
        text = tr("Failed: %1: %2")
                   .arg(QString::fromStdString(r.status), QString::fromStdString(r.message));
    }
    if (r.planform.projectedArea > 0) {  // the shape's, known even when its flow failed
        text += tr("\nhalf-span %1, projected area %2, aspect ratio %3")
                    .arg(num(r.planform.halfSpan, 5), num(r.planform.projectedArea, 5), num(r.planform.aspectRatio, 4));
    }
    if (r.index == h.latestIterate()) text += tr("\nThe optimizer's latest iterate.");
    if (e->snapshot && !e->snapshot->flow)
        text += tr("\nIts flow solution is not kept (Solve Its Flow brings the fields back).");
    panel_->setEvaluationText(text, !r.ok);
    const bool hasSnapshot = e->snapshot != nullptr;
    panel_->setEvaluationActions(
        hasSnapshot && document_->model() != nullptr,
        hasSnapshot && !e->snapshot->flow && !runner_->running() && !runner_->solvingEvaluation(),
        hasSnapshot && !e->snapshot->shape.patches.empty());
}

void OptimizationWorkspace::updateSensitivities() {
    const auto& g = runner_->history().lastGradient();
    const ffd::FfdModel* model = document_->model();
    if (!g || !g->ok || !model) {
        panel_->setSensitivities(
            {}, {}, tr("dJ/dv of every design variable appears here after the first gradient."));
        return;
    }
    // dJ/dv from the optimizer's gradient: it minimizes s J with s = -scale when maximizing, in
    // its variables u = v / range with variable_scaling "range" (study/Optimization.cpp).
    const io::CaseFile& c = document_->caseFile();
    const io::OptimizationCase& oc = c.optimization;
    const double sign = (oc.maximize ? -1.0 : 1.0) * oc.objectiveScale;
    const auto& vars = model->design().variables();
    std::vector<std::string> names;
    std::vector<double> d;
    for (std::size_t i = 0; i < vars.size() && i < g->dObjective.size(); ++i) {
        const double scale =
            oc.rangeScaling && vars[i].upper > vars[i].lower ? vars[i].upper - vars[i].lower : 1.0;
        names.push_back(vars[i].name);
        d.push_back(g->dObjective[i] / (sign * scale));
    }
    if (oc.alphaVariable && g->dObjective.size() > vars.size()) {
        const double scale = oc.rangeScaling ? oc.alphaUpper - oc.alphaLower : 1.0;
        names.push_back("alpha");
        d.push_back(g->dObjective[vars.size()] / (sign * scale));
    }
    panel_->setSensitivities(
        names, d,
        tr("d%1/dv at gradient %2 (evaluation %3's design), per unit of each variable:")
            .arg(QString::fromStdString(oc.objective))
            .arg(g->index)
            .arg(runner_->history().latestIterate()));
}

// ---- Exports
// ------------------------------------------------------------------------------------------

QString OptimizationWorkspace::askPath(const QString& title, const QString& name,
                                       const QString& filter) const {
    const QString history = runner_->historyPath();
    const QString dir = history.isEmpty() ? QDir::homePath() : QFileInfo(history).dir().path();
    return QFileDialog::getSaveFileName(dialogParent_, title, QDir(dir).filePath(name), filter);
}

void OptimizationWorkspace::chooseAndExportShape() {
    const QString path =
        askPath(tr("Export the Evaluation's Shape"),
                QStringLiteral("evaluation_%1.igs").arg(shown_, 3, 10, QLatin1Char('0')),
                tr("IGES (*.igs *.iges)"));
    if (path.isEmpty()) return;
    QString error;
    if (exportShape(path, &error))
        emit message(tr("Exported %1").arg(path), 5000);
    else
        QMessageBox::critical(dialogParent_, tr("Cannot export"), error);
}

void OptimizationWorkspace::chooseAndExportHistory() {
    const QString path = askPath(tr("Export the Optimization History"),
                                 QStringLiteral("history.csv"), tr("CSV (*.csv)"));
    if (path.isEmpty()) return;
    QString error;
    if (exportHistory(path, &error))
        emit message(tr("Exported %1 (and the iterations and JSON lines beside it)").arg(path),
                     6000);
    else
        QMessageBox::critical(dialogParent_, tr("Cannot export"), error);
}

void OptimizationWorkspace::chooseAndExportPlots() {
    const QString folder =
        QFileDialog::getExistingDirectory(dialogParent_, tr("Export the Plots into a Folder"));
    if (folder.isEmpty()) return;
    QString error;
    if (plots_->exportAll(folder, &error))
        emit message(tr("Exported the plots (PNG, SVG, CSV) into %1").arg(folder), 6000);
    else
        QMessageBox::critical(dialogParent_, tr("Cannot export"), error);
}

bool OptimizationWorkspace::exportShape(const QString& path, QString* error) const {
    const OptimizationHistory::Evaluation* e = runner_->history().evaluation(shown_);
    if (!e || !e->snapshot || e->snapshot->shape.patches.empty()) {
        if (error) *error = tr("No evaluation's shape is shown.");
        return false;
    }
    return ProjectFiles::guarded(
        [&] { study::saveGeometry(e->snapshot->shape, QFile::encodeName(path).toStdString()); },
        error);
}

bool OptimizationWorkspace::exportHistory(const QString& csvPath, QString* error) const {
    const QString csv = runner_->historyPath();
    if (csv.isEmpty() || !QFileInfo::exists(csv)) {
        if (error) *error = tr("There is no history file yet.");
        return false;
    }
    const QFileInfo from(csv),
        to(csvPath.endsWith(QLatin1String(".csv")) ? csvPath : csvPath + QStringLiteral(".csv"));
    const QString iterations =
        from.dir().filePath(from.completeBaseName() + QStringLiteral("_iterations.csv"));
    const std::vector<std::pair<QString, QString>> copies = {
        {csv, to.filePath()},
        {iterations, to.dir().filePath(to.completeBaseName() + QStringLiteral("_iterations.csv"))},
        {runner_->historyJsonlPath(),
         to.dir().filePath(to.completeBaseName() + QStringLiteral(".jsonl"))}};
    for (const auto& [source, target] : copies) {
        if (!QFileInfo::exists(source)) continue;
        if (QFileInfo(source).canonicalFilePath() == QFileInfo(target).canonicalFilePath())
            continue;
        QFile::remove(target);
        if (!QFile::copy(source, target)) {
            if (error) *error = tr("Cannot copy '%1' to '%2'.").arg(source, target);
            return false;
        }
    }
    return true;
}

bool OptimizationWorkspace::useShownDesign(QString* error) {
    const OptimizationHistory::Evaluation* e = runner_->history().evaluation(shown_);
    if (!e || !e->snapshot) {
        if (error) *error = tr("No evaluation is shown.");
        return false;
    }
    const bool alpha = document_->caseFile().optimization.alphaVariable;
    const bool ok = ProjectFiles::guarded(
        [&] {
            document_->setDesign(
                e->snapshot->values,
                alpha ? std::optional<double>(e->snapshot->alphaDeg) : std::nullopt,
                tr("Use the design of evaluation %1").arg(shown_));
        },
        error);
    if (ok) {
        setViewShown(false);  // the project's design, now the evaluation's, takes the view back
        emit message(tr("The project now has the design of evaluation %1 (undo brings the previous "
                        "one back).")
                         .arg(shown_),
                     8000);
    }
    return ok;
}

}  // namespace aero::ui
