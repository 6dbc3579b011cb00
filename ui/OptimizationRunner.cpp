#include "OptimizationRunner.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QLocale>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "Document.h"
#include "JobRunner.h"
#include "Resources.h"
#include "Text.h"
#include "common/Error.h"
#include "ffd/FfdModel.h"

namespace aero::ui {

namespace {

using Kind = study::OptimizationRecord::Kind;

QString num(double v, int digits = 4) {
    return std::isfinite(v) ? QLocale().toString(v, 'g', digits) : QStringLiteral("\u2013");
}

std::string encode(const QString& path) {
    return QFile::encodeName(path).toStdString();
}

// The status bar's line for a report of the worker (which knows the evaluation it is in).
QString statusLine(const OptimizationProgress& p, int evaluation) {
    if (p.kind == OptimizationProgress::Kind::Record) {
        const study::OptimizationRecord& r = p.record;
        if (r.kind == Kind::Values)
            return r.ok ? QObject::tr("Optimization: evaluation %1 done, J %2")
                              .arg(r.index)
                              .arg(num(r.J, 6))
                        : QObject::tr("Optimization: evaluation %1 failed (%2)")
                              .arg(r.index)
                              .arg(QString::fromStdString(r.status));
        if (r.kind == Kind::Gradient)
            return QObject::tr("Optimization: gradient %1 done").arg(r.index);
        if (r.kind == Kind::Iteration)
            return QObject::tr("Optimization: iteration %1").arg(r.index);
        return {};
    }
    if (p.kind == OptimizationProgress::Kind::Flow) {
        if (!p.flow.hasIteration) {
            QString s = QString::fromStdString(p.flow.message);
            return s.isEmpty()
                       ? QString()
                       : QObject::tr("Optimization, evaluation %1: %2").arg(evaluation).arg(s);
        }
        const flow::FlowIteration& it = p.flow.iteration;
        return QObject::tr(
                   "Optimization, evaluation %1: flow iteration %2, residual %3 of the start")
            .arg(evaluation)
            .arg(p.flow.iterationOffset + it.iteration)
            .arg(QString::number(it.relativeResidual, 'e', 2));
    }
    return {};
}

QString outcomeText(optimize::Status s) {
    switch (s) {
        case optimize::Status::Converged:
            return QObject::tr("Converged");
        case optimize::Status::IterationLimit:
            return QObject::tr("Iteration limit reached");
        case optimize::Status::EvaluationLimit:
            return QObject::tr("Evaluation limit reached");
        case optimize::Status::Cancelled:
            return QObject::tr("Stopped");
        case optimize::Status::Stalled:
            return QObject::tr("Stalled");
        case optimize::Status::Infeasible:
            return QObject::tr("No feasible design found");
        case optimize::Status::Failed:
            return QObject::tr("The optimizer failed");
    }
    return {};
}

// libcore's messages name the command line's options; the window has buttons for them.
QString inWindowTerms(QString why) {
    why.replace(QStringLiteral("start over with --fresh"),
                QObject::tr("Start Over replaces the history"));
    why.replace(QStringLiteral(" (--resume)"), QString());
    why.replace(QStringLiteral(" (--fresh)"), QString());
    return why;
}

}  // namespace

struct OptimizationRunner::Slot {
    std::optional<OptimizationRunResult> run;
};

OptimizationRunner::OptimizationRunner(Document* document, JobRunner* jobs, QObject* parent)
    : QObject(parent), document_(document), jobs_(jobs) {
    history_.setKeptFlows(
        std::max(1, setting(QStringLiteral("optimization/keptSolutions")).toInt()));
    connect(document_, &Document::reset, this, &OptimizationRunner::onReset);
}

OptimizationRunner::~OptimizationRunner() = default;

// ---- Paths ------------------------------------------------------------------------------------

QString OptimizationRunner::historyPath() const {
    const io::CaseFile& c = document_->caseFile();
    if (!c.optimization.history.empty()) return QFile::decodeName(c.optimization.history.c_str());
    const QString project = document_->projectPath();
    if (project.isEmpty()) return {};
    const QFileInfo info(project);
    // The case parser's default (io/CaseFile.cpp): <stem>.history.csv beside the case.
    return info.dir().filePath(info.completeBaseName() + QStringLiteral(".history.csv"));
}

QString OptimizationRunner::historyJsonlPath() const {
    const QString csv = historyPath();
    return csv.isEmpty() ? QString()
                         : QFile::decodeName(study::historyJsonlPath(encode(csv)).c_str());
}

bool OptimizationRunner::historyExists() const {
    const QFileInfo info(historyJsonlPath());
    return !historyJsonlPath().isEmpty() && info.exists() && info.size() > 0;
}

bool OptimizationRunner::runCase(io::CaseFile& c, QString* error) const {
    auto fail = [error](const QString& why) {
        if (error) *error = why;
        return false;
    };
    if (!document_->hasGeometry()) return fail(tr("Open a geometry first."));
    c = document_->caseFile();
    if (!c.optimization.present)
        return fail(
            tr("The case has no optimization yet: choose its objective and limits in the "
               "Optimization panel."));
    if (!document_->model() || document_->model()->design().size() == 0)
        return fail(
            tr("The case has no design variables to optimize: add a lattice with station variables "
               "first."));
    const QString history = historyPath();
    if (history.isEmpty())
        return fail(
            tr("Save the project first: the optimization keeps its history beside it "
               "(optimization.history)."));
    c.optimization.history = encode(history);
    c.flow.present = true;
    return true;
}

// ---- Running ------------------------------------------------------------------------------------

bool OptimizationRunner::start(Start how, QString* error) {
    if (job_ || loadJob_) {
        if (error)
            *error = tr("An optimization is running: one at a time. Pause or stop it first.");
        return false;
    }
    io::CaseFile c;
    if (!runCase(c, error)) return false;
    const bool exists = historyExists();
    if (how == Start::New && exists) {
        if (error)
            *error = tr("The history %1 exists: resume it, or start over (which replaces it).")
                         .arg(historyJsonlPath());
        return false;
    }
    if (how == Start::Resume && !exists) {
        if (error)
            *error =
                tr("There is no history to resume (%1 does not exist).").arg(historyJsonlPath());
        return false;
    }
    auto input = std::make_shared<OptimizationRunInput>();
    input->baseline = document_->baseline();
    input->caseFile = std::move(c);
    input->resume = how == Start::Resume;
    input->fresh = how == Start::Fresh;
    pause_ = std::make_shared<std::atomic<bool>>(false);
    input->pause = pause_;
    slot_ = std::make_shared<Slot>();
    reason_.clear();
    outcome_.reset();
    stopRequested_ = false;
    lastNewEvaluation_ = 0;
    if (how != Start::Resume) {
        history_.clear();
        emit historyReset();
    }
    runGeneration_ = generation_;
    const quint64 generation = generation_;
    QPointer<OptimizationRunner> self(this);

    JobSpec<OptimizationProgress> spec;
    spec.title = tr("Optimization");
    spec.kind = QStringLiteral("optimization");
    spec.work = [input, slot = slot_](const JobContext<OptimizationProgress>& ctx) {
        int evaluation = 1;  // the evaluation the flow reports belong to
        auto report = [&ctx, &evaluation](OptimizationProgress p) {
            if (p.kind == OptimizationProgress::Kind::Record && p.record.kind == Kind::Values)
                evaluation = p.record.index + 1;
            if (p.kind != OptimizationProgress::Kind::Log) {
                const QString line = statusLine(p, evaluation);
                if (!line.isEmpty()) ctx.status(-1, line);
            }
            ctx.report(std::move(p));
        };
        slot->run =
            runOptimization(*input, report, ctx.cancelFlag(), [&ctx] { ctx.requestCancel(); });
    };
    spec.progress = [self, generation](const OptimizationProgress& p) {
        if (self && generation == self->generation_) self->onReport(p);
    };
    job_ = jobs_->start(std::move(spec));
    connect(job_, &Job::finished, this, &OptimizationRunner::onJobFinished);
    setState(State::Running);
    emit started(how == Start::Resume);
    emit message(how == Start::Resume
                     ? tr("Optimization: resuming %1").arg(historyJsonlPath())
                     : tr("Optimization started; its history goes to %1").arg(historyPath()),
                 6000);
    return true;
}

void OptimizationRunner::pause() {
    if (!job_ || state_ != State::Running) return;
    pause_->store(true);
    setState(State::Pausing);
    emit message(tr("The optimization pauses after the evaluation (or gradient) it is computing."),
                 8000);
}

void OptimizationRunner::stop() {
    if (!job_) return;
    stopRequested_ = true;
    job_->cancel();
    emit stateChanged();  // the text says it is stopping
}

bool OptimizationRunner::running() const {
    return !job_.isNull();
}

Job* OptimizationRunner::job() const {
    return job_.data();
}

int OptimizationRunner::currentEvaluation() const {
    if (!job_) return 0;
    return history_.evaluationCount() + 1;
}

void OptimizationRunner::onReport(const OptimizationProgress& p) {
    switch (p.kind) {
        case OptimizationProgress::Kind::Record:
            if (p.record.kind == Kind::Values && !p.record.replayed)
                lastNewEvaluation_ = p.record.index;
            history_.add(p.record, p.snapshot);
            emit recordAdded(p.record);
            if (p.record.kind == Kind::Values) emit stateChanged();  // the running text names it
            break;
        case OptimizationProgress::Kind::Flow:
            emit flowReported(p.flow);
            break;
        case OptimizationProgress::Kind::Log:
            emit logged(QString::fromStdString(p.line));
            break;
    }
}

void OptimizationRunner::onJobFinished() {
    if (!job_) return;
    const Job::State how = job_->state();
    const QString error = job_->error();
    job_ = nullptr;
    std::shared_ptr<Slot> slot = std::move(slot_);
    if (runGeneration_ != generation_) {  // the run belonged to a document since replaced
        emit stateChanged();
        loadHistoryOfProject();
        return;
    }
    if (how == Job::State::Failed || !slot || !slot->run) {
        reason_ =
            how == Job::State::Failed ? inWindowTerms(error) : tr("the run ended without a result");
        if (how == Job::State::Cancelled && (!slot || !slot->run)) {
            setState(State::Stopped);  // cancelled before the optimizer started
        } else {
            setState(State::Failed);
            emit message(tr("Optimization failed: %1").arg(reason_), 30000);
        }
        return;
    }
    const OptimizationRunResult& r = *slot->run;
    summary_ = r.summary;
    if (r.summary) {
        outcome_ = r.summary->result.status;
        reason_ = QString::fromStdString(r.summary->result.message);
    }
    // A stop ends the optimizer in whatever way it takes a failed evaluation (at the start point
    // Ipopt gives up as "failed"): the user's stop is what happened.
    const bool stopped = stopRequested_ || (how == Job::State::Cancelled && !r.paused);
    State next = State::Finished;
    if (r.paused && !stopRequested_)
        next = State::Paused;
    else if (stopped || !outcome_ || *outcome_ == optimize::Status::Cancelled)
        next = State::Stopped;
    setState(next);
    emit message(stateText(), next == State::Finished ? 15000 : 30000);
}

void OptimizationRunner::setState(State s) {
    state_ = s;
    emit stateChanged();
}

QString OptimizationRunner::stateText() const {
    const int n = history_.evaluationCount();
    const int failed = history_.failedEvaluations();
    const QString evaluations = counted(n, tr("evaluation"), tr("evaluations")) +
                                (failed > 0 ? tr(" (%1 failed)").arg(failed) : QString());
    const OptimizationHistory::Evaluation* last = history_.evaluation(n);
    auto lastFailure = [&]() -> QString {
        if (!last || last->record.ok) return {};
        return tr("; evaluation %1 failed: %2: %3")
            .arg(last->record.index)
            .arg(QString::fromStdString(last->record.status),
                 QString::fromStdString(last->record.message));
    };
    switch (state_) {
        case State::None:
            return {};
        case State::Running:
            if (stopRequested_) return tr("Stopping within the current flow iteration...");
            return tr("Running: evaluation %1%2").arg(n + 1).arg(lastFailure());
        case State::Pausing:
            if (stopRequested_) return tr("Stopping within the current flow iteration...");
            return tr("Pausing after evaluation %1 (or its gradient)...").arg(n + 1);
        case State::Paused:
            return tr("Paused after %1: the history ends on a whole record; Resume continues it.")
                .arg(evaluations);
        case State::Stopped:
            return tr("Stopped with %1 recorded; an interrupted evaluation is solved again on "
                      "Resume.")
                .arg(evaluations);
        case State::Finished: {
            QString s = outcome_ ? outcomeText(*outcome_) : tr("Finished");
            if (summary_)
                s += tr(" after %1 iterations, %2")
                         .arg(summary_->result.iterations)
                         .arg(evaluations);
            if (!reason_.isEmpty()) s += QStringLiteral(": ") + reason_;
            return s + QLatin1Char('.');
        }
        case State::Failed:
            return tr("Failed: %1").arg(reason_);
        case State::Recorded:
            return tr("History of %1 read from %2; Resume continues it, Start Over replaces it.")
                .arg(evaluations, QFileInfo(historyJsonlPath()).fileName());
    }
    return {};
}

// ---- Reading a history back
// --------------------------------------------------------------------------

bool OptimizationRunner::loadHistory(QString* error) {
    if (job_ || loadJob_) {
        if (error) *error = tr("An optimization is running.");
        return false;
    }
    io::CaseFile c;
    if (!runCase(c, error)) return false;
    if (!historyExists()) {
        if (error) *error = tr("There is no history (%1 does not exist).").arg(historyJsonlPath());
        return false;
    }
    auto baseline = std::make_shared<geometry::PatchSet>(document_->baseline());
    auto input = std::make_shared<io::CaseFile>(std::move(c));
    auto loaded = std::make_shared<std::optional<LoadedHistory>>();
    const quint64 generation = generation_;
    JobSpec<NoProgress> spec;
    spec.title = tr("Reading the optimization history");
    spec.kind = QStringLiteral("optimization-history");
    spec.work = [baseline, input, loaded](const JobContext<NoProgress>& ctx) {
        ctx.status(-1, QObject::tr("Reading the optimization history and its shapes"));
        *loaded = loadOptimizationHistory(*baseline, *input, ctx.cancelFlag());
    };
    QPointer<OptimizationRunner> self(this);
    loadJob_ = jobs_->start(std::move(spec));
    Job* job = loadJob_.data();
    connect(job, &Job::finished, this, [self, generation, job, loaded] {
        if (!self) return;
        self->loadJob_ = nullptr;
        if (generation != self->generation_) {
            self->loadHistoryOfProject();  // the old document's reading ended: the new one's may
                                           // start
            return;
        }
        self->onLoadFinished(job->state() == Job::State::Finished ? *loaded : std::nullopt,
                             job->error());
    });
    return true;
}

bool OptimizationRunner::loading() const {
    return !loadJob_.isNull();
}

void OptimizationRunner::onLoadFinished(const std::optional<LoadedHistory>& loaded,
                                        const QString& error) {
    if (!loaded) {
        if (!error.isEmpty())
            emit message(tr("Cannot read the optimization history: %1").arg(error), 15000);
        return;
    }
    history_.clear();
    std::size_t s = 0;
    for (const study::OptimizationRecord& r : loaded->records) {
        std::shared_ptr<const EvaluationSnapshot> snapshot;
        if (r.kind == Kind::Values && s < loaded->snapshots.size())
            snapshot = loaded->snapshots[s++];
        history_.add(r, snapshot);
    }
    outcome_.reset();
    summary_.reset();
    reason_.clear();
    state_ = State::Recorded;  // before the history's listeners look (the view shows a read-back
                               // history)
    emit historyReset();
    emit stateChanged();
}

void OptimizationRunner::loadHistoryOfProject() {
    if (state_ != State::None || job_ || loadJob_ || !history_.empty()) return;
    if (document_->hasGeometry() && document_->caseFile().optimization.present && historyExists())
        loadHistory();
}

// ---- An evaluation's flow, solved again
// -------------------------------------------------------------

bool OptimizationRunner::solveEvaluationFlow(int index, QString* error) {
    const OptimizationHistory::Evaluation* e = history_.evaluation(index);
    if (!e || !e->snapshot) {
        if (error) *error = tr("There is no evaluation %1.").arg(index);
        return false;
    }
    if (flowJob_) {
        if (error) *error = tr("An evaluation's flow is being solved already.");
        return false;
    }
    if (job_) {
        if (error) *error = tr("Pause the optimization first: its flow solves have the machine.");
        return false;
    }
    io::CaseFile c;
    if (!runCase(c, error)) return false;
    const ffd::FfdModel* model = document_->model();
    const auto& vars = model->design().variables();
    auto input = std::make_shared<FlowRunInput>();
    input->baseline = document_->baseline();
    for (std::size_t i = 0; i < vars.size() && i < e->snapshot->values.size(); ++i)
        c.values[vars[i].name] = e->snapshot->values[i];
    c.flow.freeStream.alphaDeg = e->snapshot->alphaDeg;
    input->caseFile = std::move(c);
    // The run kept the converged states of its newest evaluations for its warm starts: such a
    // flow comes back in an iteration or two instead of a whole solve.
    const QString csv = historyPath();
    if (!csv.isEmpty()) input->warmStateFrom = study::warmStatePath(encode(csv), index);
    auto result = std::make_shared<std::shared_ptr<FlowRunResult>>();
    auto snapshot = e->snapshot;
    const quint64 generation = generation_;
    JobSpec<FlowRunProgress> spec;
    spec.title = tr("Flow of evaluation %1").arg(index);
    spec.kind = QStringLiteral("optimization-flow");
    spec.work = [input, result](const JobContext<FlowRunProgress>& ctx) {
        *result = std::make_shared<FlowRunResult>(runFlowSolve(
            *input,
            [&ctx](const FlowRunProgress& p) {
                if (p.hasIteration)
                    ctx.status(-1, QObject::tr("Flow iteration %1, residual %2 of the start")
                                       .arg(p.iteration.iteration)
                                       .arg(QString::number(p.iteration.relativeResidual, 'e', 2)));
                ctx.report(p);
            },
            ctx.cancelFlag()));
    };
    QPointer<OptimizationRunner> self(this);
    spec.progress = [self, generation](const FlowRunProgress& p) {
        if (self && generation == self->generation_) emit self->flowReported(p);
    };
    spec.done = [self, generation, result, snapshot, index] {
        if (!self || generation != self->generation_ || !*result || !(*result)->flow) return;
        auto next = std::make_shared<EvaluationSnapshot>(*snapshot);
        next->flow = *result;
        self->history_.setSnapshot(index, next);
        emit self->snapshotChanged(index);
        const study::FlowResult& f = *(*result)->flow;
        QString text;
        if ((*result)->status != study::EvaluationStatus::Ok)
            text = tr("The flow of evaluation %1: %2").arg(index).arg(QString::fromStdString((*result)->message));
        else if (f.warmStarted)
            text = tr("The flow of evaluation %1 is back from the state the run kept (%2 iterations).")
                       .arg(index)
                       .arg(f.report.iterations);
        else
            text = tr("The flow of evaluation %1 is solved again.").arg(index);
        emit self->message(text, 8000);
    };
    flowJob_ = jobs_->start(std::move(spec));
    return true;
}

bool OptimizationRunner::solvingEvaluation() const {
    return !flowJob_.isNull();
}

// ---- Following the document
// ----------------------------------------------------------------------

void OptimizationRunner::onReset() {
    ++generation_;  // jobs still running belong to the previous document (they end on their own)
    if (job_) job_->cancel();
    if (loadJob_) loadJob_->cancel();
    if (flowJob_) flowJob_->cancel();
    history_.clear();
    outcome_.reset();
    summary_.reset();
    reason_.clear();
    stopRequested_ = false;
    emit historyReset();
    setState(State::None);
    // A project whose optimization was interrupted (closed, crashed): read its history back
    // (once the old document's jobs have ended).
    loadHistoryOfProject();
}

}  // namespace aero::ui
