#include "SensitivityRunner.h"

#include <QLocale>

#include "Document.h"
#include "FlowRunner.h"
#include "JobRunner.h"

namespace aero::ui {

namespace {

QString signedNumber(double v) {
    return (v >= 0 ? QStringLiteral("+") : QString()) + QLocale().toString(v, 'g', 4);
}

bool sameLattices(const std::vector<ffd::Lattice>& a, const std::vector<ffd::Lattice>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t l = 0; l < a.size(); ++l)
        if (a[l].points != b[l].points) return false;
    return true;
}

}  // namespace

SensitivityRunner::SensitivityRunner(Document* document, JobRunner* jobs, FlowRunner* flow, QObject* parent)
    : QObject(parent), document_(document), jobs_(jobs), flow_(flow) {
    connect(document_, &Document::valuesChanged, this, &SensitivityRunner::onDesignChanged);
    connect(document_, &Document::latticesMoved, this, &SensitivityRunner::onDesignChanged);
    for (auto changed : {&Document::structureChanged, &Document::meshOptionsChanged, &Document::flowOptionsChanged,
                         &Document::optimizationOptionsChanged})
        connect(document_, changed, this, &SensitivityRunner::drop);
    connect(document_, &Document::reset, this, [this] {
        ++generation_;  // a job still running belongs to the previous document
        if (job_) job_->cancel();
        drop();
        reason_.clear();
        if (state_ != State::Running) {
            state_ = State::None;
            emit stateChanged(state_);
        }
    });
    connect(flow_, &FlowRunner::stateChanged, this, &SensitivityRunner::onFlowResult);
}

SensitivityRunner::~SensitivityRunner() = default;

Objective SensitivityRunner::objective() const {
    return chosen_ ? *chosen_ : caseObjective(document_->caseFile());
}

void SensitivityRunner::setObjective(std::optional<Objective> chosen) {
    const Objective before = objective();
    chosen_ = std::move(chosen);
    const Objective now = objective();
    if (now.name != before.name || now.maximize != before.maximize) drop();
}

double SensitivityRunner::improvingSign() const {
    const Objective o = result_ ? result_->objective : objective();
    return o.maximize ? 1.0 : -1.0;
}

bool SensitivityRunner::start(QString* error) {
    if (!document_->hasGeometry() || !document_->model()) {
        if (error) *error = tr("Sensitivities need a geometry with a lattice (FFD \u25b8 Add Lattice).");
        return false;
    }
    if (job_) {
        if (error) *error = tr("Sensitivities are being computed: one computation at a time.");
        return false;
    }
    auto input = std::make_shared<SensitivityInput>();
    input->baseline = document_->baseline();
    input->caseFile = document_->caseFile();
    input->caseFile.flow.present = true;
    input->objective = objective();
    // A converged solution of this very design and grid is the best start (a few iterations).
    if (const auto r = flow_->result();
        r && r->flow && r->converged() && !flow_->outdated() && flow_->state() == FlowRunner::State::Converged)
        input->warmState = r->flow->q;
    slot_ = std::make_shared<std::shared_ptr<SensitivityResult>>();
    reason_.clear();
    runGeneration_ = generation_;
    job_ = jobs_->start(
        tr("Sensitivities"), QStringLiteral("sensitivities"),
        [input, slot = slot_](const JobContext<NoProgress>& ctx) {
            *slot = std::make_shared<SensitivityResult>(runSensitivities(
                *input, [&ctx](double fraction, const std::string& line) { ctx.status(fraction, QString::fromStdString(line)); },
                ctx.cancelFlag()));
        });
    connect(job_, &Job::finished, this, &SensitivityRunner::onJobFinished);
    state_ = State::Running;
    emit stateChanged(state_);
    emit message(tr("Computing the sensitivities of %1: the flow, then its adjoint.").arg(QString::fromStdString(input->objective.name)),
                 4000);
    return true;
}

void SensitivityRunner::cancel() {
    if (job_) job_->cancel();
}

void SensitivityRunner::onJobFinished() {
    if (!job_) return;
    const Job::State how = job_->state();
    const QString error = job_->error();
    job_ = nullptr;
    std::shared_ptr<SensitivityResult> r = slot_ ? *slot_ : nullptr;
    slot_.reset();
    if (runGeneration_ != generation_) {
        state_ = State::None;
        emit stateChanged(state_);
        return;
    }
    if (how == Job::State::Cancelled) {
        reason_ = tr("cancelled");
        state_ = State::Failed;
        emit stateChanged(state_);
        emit message(tr("Sensitivities cancelled."), 6000);
        return;
    }
    if (how == Job::State::Failed || !r || !r->ok) {
        reason_ = how == Job::State::Failed ? error : r ? QString::fromStdString(r->message) : tr("the run ended without a result");
        state_ = State::Failed;
        emit stateChanged(state_);
        emit message(tr("No sensitivities: %1").arg(reason_), 30000);
        return;
    }
    result_ = r;
    confirmed_.reset();
    confirming_ = false;
    outdated_ = !matchesDocument();
    state_ = State::Done;
    emit resultChanged();
    emit outdatedChanged(outdated_);
    emit predictionChanged();
    emit stateChanged(state_);
    emit message(tr("Sensitivities of %1 = %2: flow %3 s, adjoint gradient %4 s.")
                     .arg(QString::fromStdString(r->objective.name))
                     .arg(QLocale().toString(r->J, 'g', 5))
                     .arg(QLocale().toString(r->secondsFlow, 'f', 1))
                     .arg(QLocale().toString(r->secondsGradient, 'f', 1)),
                 10000);
}

bool SensitivityRunner::matchesDocument() const {
    return result_ && document_->values() == result_->values && sameLattices(document_->lattices(), result_->lattices);
}

void SensitivityRunner::onDesignChanged() {
    if (!result_) return;
    const bool now = !matchesDocument();
    if (confirmed_ && !sameLattices(document_->lattices(), confirmedLattices_)) confirmed_.reset();
    if (now != outdated_) {
        outdated_ = now;
        emit outdatedChanged(outdated_);
    }
    emit predictionChanged();
}

void SensitivityRunner::drop() {
    confirming_ = false;
    confirmed_.reset();
    if (!result_) return;
    result_.reset();
    outdated_ = false;
    emit resultChanged();
    emit predictionChanged();
}

std::optional<double> SensitivityRunner::prediction() const {
    return result_ ? predictedChange(*result_, document_->lattices()) : std::nullopt;
}

QString SensitivityRunner::predictionText() const {
    const std::optional<double> dJ = prediction();
    if (!result_ || !dJ) return {};
    const QString name = QString::fromStdString(result_->objective.name);
    QString s = tr("Predicted \u0394%1 = %2 (first order, from %3 = %4)")
                    .arg(name, signedNumber(*dJ), name, QLocale().toString(result_->J, 'g', 5));
    if (confirmed_)
        s += tr("; flow solve: \u0394%1 = %2").arg(name, signedNumber(*confirmed_));
    else if (confirming_)
        s += tr("; confirming with a flow solve...");
    return s;
}

bool SensitivityRunner::confirm(QString* error) {
    if (!result_) {
        if (error) *error = tr("Compute the sensitivities first (Flow \u25b8 Compute Sensitivities).");
        return false;
    }
    if (!flow_->start(error)) return false;
    confirming_ = true;
    confirmed_.reset();
    confirmedLattices_ = document_->lattices();
    emit predictionChanged();
    return true;
}

void SensitivityRunner::onFlowResult() {
    if (!confirming_ || flow_->state() == FlowRunner::State::Running) return;
    confirming_ = false;
    const auto r = flow_->result();
    if (flow_->state() == FlowRunner::State::Converged && result_ && r && r->flow && !flow_->outdated() &&
        sameLattices(document_->lattices(), confirmedLattices_)) {
        if (const std::optional<double> J = objectiveValue(result_->objective.name, r->flow->forces))
            confirmed_ = *J - result_->J;
    } else {
        emit message(tr("The confirming flow solve did not give a converged solution of this design."), 8000);
    }
    emit predictionChanged();
}

}  // namespace aero::ui
