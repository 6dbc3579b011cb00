#include "FlowRunner.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QLocale>
#include <algorithm>
#include <cmath>

#include "Document.h"
#include "JobRunner.h"
#include "common/Error.h"
#include "io/CaseWriter.h"
#include "io/FlowFiles.h"

namespace aero::ui {

namespace {

QString num(double v, int digits = 3) {
    return QLocale().toString(v, 'g', digits);
}

// Seconds for people: "4.2", "96", "1,475".
QString seconds(double s) {
    return s >= 100 ? QLocale().toString(s, 'f', 0) : QLocale().toString(s, 'g', 2);
}

// The status bar's line and fraction for a report.
QString statusLine(const FlowRunProgress& p) {
    if (!p.hasIteration) {
        QString s = QString::fromStdString(p.message);
        if (!s.isEmpty()) s[0] = s[0].toUpper();
        return s;
    }
    const flow::FlowIteration& it = p.iteration;
    const int n = p.iterationOffset + it.iteration;
    if (!it.rejected.empty())
        return QObject::tr("Flow: iteration %1 rejected at CFL %2 (%3)").arg(n).arg(num(it.cfl)).arg(QString::fromStdString(it.rejected));
    return QObject::tr("Flow%1: iteration %2, residual %3 of the start, CFL %4, %5 GMRES")
        .arg(p.coarse ? QObject::tr(" (coarse grid)") : QString())
        .arg(n)
        .arg(QString::number(it.relativeResidual, 'e', 2))
        .arg(num(it.cfl))
        .arg(it.linearIterations);
}

}  // namespace

FlowRunner::FlowRunner(Document* document, JobRunner* jobs, QObject* parent)
    : QObject(parent), document_(document), jobs_(jobs) {
    connect(document_, &Document::shapeChanged, this, &FlowRunner::onDocumentChanged);
    connect(document_, &Document::meshOptionsChanged, this, &FlowRunner::onDocumentChanged);
    connect(document_, &Document::flowOptionsChanged, this, &FlowRunner::onDocumentChanged);
    connect(document_, &Document::reset, this, &FlowRunner::onReset);
}

FlowRunner::~FlowRunner() = default;

// ---- Running ------------------------------------------------------------------------------------

bool FlowRunner::start(QString* error, bool continueRun) {
    if (!document_->hasGeometry()) {
        if (error) *error = tr("Open a geometry first.");
        return false;
    }
    if (job_) {
        if (error) *error = tr("A flow solve is running: one at a time. Stop it first.");
        return false;
    }
    // Copies for the worker: it never touches the document.
    auto input = std::make_shared<FlowRunInput>();
    input->baseline = document_->baseline();
    input->caseFile = document_->caseFile();
    input->caseFile.flow.present = true;
    input->wall = document_->uniquePoints();
    input->restartTo = QFile::encodeName(restartPath()).toStdString();
    input->restartAlways = !input->caseFile.outputRestart.empty();  // the case asks for it, as the CLI
    if (continueRun) {
        if (!canContinue()) {
            if (error) *error = tr("There is no stopped run to continue (no restart file).");
            return false;
        }
        input->restartFrom = input->restartTo;
    }
    const double tolerance = input->caseFile.flow.newton.relativeTolerance;
    slot_ = std::make_shared<std::shared_ptr<FlowRunResult>>();
    reports_.clear();
    reason_.clear();
    continued_ = continueRun;
    runningOptions_ = optionsKey();
    const quint64 generation = generation_;
    runGeneration_ = generation_;
    QPointer<FlowRunner> self(this);

    JobSpec<FlowRunProgress> spec;
    spec.title = tr("Flow solve");
    spec.kind = QStringLiteral("flow");
    spec.work = [input, slot = slot_, tolerance](const JobContext<FlowRunProgress>& ctx) {
        auto progress = [&ctx, tolerance](const FlowRunProgress& p) {
            double fraction = -1;
            if (p.hasIteration && p.iteration.rejected.empty() && !p.coarse && p.iteration.relativeResidual > 0)
                fraction = std::clamp(std::log10(p.iteration.relativeResidual) / std::log10(tolerance), 0.0, 1.0);
            ctx.status(fraction, statusLine(p));
            ctx.report(p);
        };
        *slot = std::make_shared<FlowRunResult>(runFlowSolve(*input, progress, ctx.cancelFlag()));
    };
    spec.progress = [self, generation](const FlowRunProgress& p) {
        if (self && generation == self->generation_) self->onReport(p);
    };
    job_ = jobs_->start(std::move(spec));
    connect(job_, &Job::finished, this, &FlowRunner::onJobFinished);
    setState(State::Running);
    emit started();
    emit message(continueRun ? tr("Flow solve: continuing from %1").arg(restartPath()) : tr("Flow solve started."), 4000);
    return true;
}

bool FlowRunner::running() const {
    return !job_.isNull();
}

Job* FlowRunner::job() const {
    return job_.data();
}

void FlowRunner::stop() {
    if (job_) job_->cancel();
}

void FlowRunner::onReport(const FlowRunProgress& p) {
    reports_.push_back(p);
    emit reported(p);
}

int FlowRunner::acceptedIterations() const {
    return static_cast<int>(std::count_if(reports_.begin(), reports_.end(), [](const FlowRunProgress& p) {
        return p.hasIteration && p.iteration.rejected.empty() && !p.coarse;
    }));
}

void FlowRunner::onJobFinished() {
    if (!job_) return;
    const Job::State how = job_->state();
    const QString error = job_->error();
    job_ = nullptr;
    // The worker has ended: its result slot is ours (also after a cancel, when `done` is not
    // called: a stopped run's state is shown too).
    std::shared_ptr<FlowRunResult> r = slot_ ? *slot_ : nullptr;
    slot_.reset();
    if (runGeneration_ != generation_) {  // the run belonged to a document since replaced
        emit stateChanged(state_);         // (None) but it is over: Solve is possible again
        return;
    }
    if (how == Job::State::Failed || !r) {
        reason_ = how == Job::State::Failed ? error : tr("the run ended without a result");
        setState(State::Failed);
        emit message(tr("Flow solve failed: %1").arg(reason_), 30000);
        return;
    }
    reason_ = QString::fromStdString(r->message);
    State next = State::Converged;
    switch (r->status) {
        case study::EvaluationStatus::Ok:
            next = State::Converged;
            break;
        case study::EvaluationStatus::FlowNotConverged:
            next = State::NotConverged;
            break;
        case study::EvaluationStatus::Cancelled:
            next = State::Stopped;
            break;
        case study::EvaluationStatus::InvalidShape:
        case study::EvaluationStatus::InvalidMesh:
            next = State::Failed;
            break;
    }
    if (how == Job::State::Cancelled && next == State::Converged) next = State::Stopped;  // stopped at the very end
    if (r->flow) {
        result_ = r;
        resultOptions_ = runningOptions_;
        const bool wasOutdated = outdated_;
        outdated_ = !matchesDocument();
        emit resultChanged();
        if (wasOutdated != outdated_) emit outdatedChanged(outdated_);
    }
    setState(next);
    emit message(stateText(), next == State::Converged ? 10000 : 30000);
}

void FlowRunner::setState(State s) {
    if (s == state_ && s != State::Running) return;
    state_ = s;
    emit stateChanged(s);
}

QString FlowRunner::stateText() const {
    const FlowRunResult* r = result_.get();
    const int iterations = r && r->flow ? r->flow->report.iterations : acceptedIterations();
    const int offset = r && r->flow && r->flow->restartContinued ? r->flow->previousIterations : 0;
    switch (state_) {
        case State::None:
            return {};
        case State::Running:
            return tr("Running: iteration %1").arg(acceptedIterations());
        case State::Converged:
            return tr("Converged in %1 (%2 s): residual %3 of the start")
                .arg(iterations + offset == 1 ? tr("1 iteration") : tr("%1 iterations").arg(iterations + offset))
                .arg(seconds(r ? r->seconds : 0))
                .arg(r && r->flow && r->flow->report.initialResidual > 0
                         ? QString::number(r->flow->report.finalResidual / r->flow->report.initialResidual, 'e', 1)
                         : QStringLiteral("-"));
        case State::NotConverged:
            return tr("Not converged: %1").arg(reason_);
        case State::Stopped: {
            QString s = tr("Stopped at iteration %1; the state reached is shown").arg(iterations + offset);
            if (r && !r->restartWritten.empty())
                s += tr(" and kept in %1 (Continue resumes it)").arg(QString::fromStdString(r->restartWritten));
            else if (r && !r->restartError.empty())
                s += tr(" (not kept: %1)").arg(QString::fromStdString(r->restartError));
            return s + QLatin1Char('.');
        }
        case State::Failed:
            return tr("Failed: %1").arg(reason_);
    }
    return {};
}

// ---- Following the document ----------------------------------------------------------------------

std::string FlowRunner::optionsKey() const {
    io::CaseFile k;
    k.mesh = document_->caseFile().mesh;
    k.mesh.present = true;
    k.flow = document_->caseFile().flow;
    k.flow.present = true;
    return io::formatCase(k);
}

bool FlowRunner::matchesDocument() const {
    return result_ && document_->hasGeometry() && optionsKey() == resultOptions_ && document_->uniquePoints() == result_->wall;
}

void FlowRunner::onDocumentChanged() {
    if (!result_) return;
    const bool now = !matchesDocument();
    if (now == outdated_) return;
    outdated_ = now;
    emit outdatedChanged(outdated_);
    emit message(outdated_ ? tr("The flow solution is outdated (the geometry or the case's options changed) and was "
                                "taken off the view; solve again, or undo to get it back.")
                           : tr("The flow solution matches the case again."),
                 8000);
}

void FlowRunner::onReset() {
    ++generation_;  // a job still running belongs to the previous document
    if (job_) job_->cancel();
    const bool had = result_ != nullptr;
    result_.reset();
    reports_.clear();
    reason_.clear();
    outdated_ = false;
    if (had) emit resultChanged();
    setState(State::None);
}

// ---- Files ------------------------------------------------------------------------------------------

QString FlowRunner::restartPath() const {
    const io::CaseFile& c = document_->caseFile();
    if (!c.outputRestart.empty()) return QFile::decodeName(c.outputRestart.c_str());
    const QString project = document_->projectPath();
    if (project.isEmpty()) return {};
    const QFileInfo info(project);
    return info.dir().filePath(info.completeBaseName() + QStringLiteral(".restart"));
}

bool FlowRunner::canContinue() const {
    const QString path = restartPath();
    return !path.isEmpty() && QFileInfo::exists(path);
}

void FlowRunner::exportSolution(const QString& path) const {
    if (!result_ || !result_->flow) throw InputError("no flow solution to export: run Flow > Solve first");
    const study::FlowResult& f = *result_->flow;
    io::writeFlowVtm(QFile::encodeName(path).toStdString(), f.mesh, f.x, f.q, f.residualOptions.freeStream);
}

}  // namespace aero::ui
