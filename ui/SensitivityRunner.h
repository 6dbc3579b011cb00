#pragma once
// Flow > Compute Sensitivities: runs SensitivityRun.h's pipeline (the design's flow and the
// adjoint gradient of the objective) as a job of the JobRunner on a copy of the document's case,
// one at a time, cancellable, and keeps the result for the places a designer looks: dJ/dv next
// to the sliders, dJ/dB as arrows at the lattice points, and the first-order change of J for
// the design as it is now (a drag's preview included): dJ = sum dJ/dB . (B - B0). The prediction
// is confirmed on request by a flow solve (the FlowRunner's) of the design as shown: the actual
// change of J is then reported next to the predicted one.
//
// The result follows the document: it is *current* while the design is the one differentiated;
// once values or lattice points change it is kept (the prediction needs it) but outdated; a
// change of the case's mesh or flow options, of the lattices' structure or a new project drops it.
//
// GUI thread only; no VTK. The worker never sees the Document.
#include <QObject>
#include <QPointer>
#include <QString>
#include <memory>
#include <optional>

#include "SensitivityRun.h"

namespace aero::ui {

class Document;
class FlowRunner;
class Job;
class JobRunner;

class SensitivityRunner : public QObject {
    Q_OBJECT

  public:
    enum class State { None, Running, Done, Failed };

    SensitivityRunner(Document* document, JobRunner* jobs, FlowRunner* flow, QObject* parent = nullptr);
    ~SensitivityRunner() override;

    /// Starts the computation for the document as shown. False (with *error) without geometry or
    /// lattices, or while one runs.
    bool start(QString* error = nullptr);
    void cancel();
    bool running() const { return !job_.isNull(); }
    Job* job() const { return job_.data(); }

    State state() const { return state_; }
    /// Why the last run failed (empty otherwise).
    QString reason() const { return reason_; }
    /// The last successful result (null when none or dropped).
    std::shared_ptr<const SensitivityResult> result() const { return result_; }
    /// The design changed since the result was computed.
    bool outdated() const { return outdated_; }
    /// The objective the next run differentiates: the chosen one, else the case's (caseObjective).
    Objective objective() const;
    /// Chooses the objective (nullopt: the case's). A different choice drops the result.
    void setObjective(std::optional<Objective> chosen);
    std::optional<Objective> chosenObjective() const { return chosen_; }
    /// +1 when the objective is maximized, -1 when minimized (the direction that improves it).
    double improvingSign() const;

    /// First order change of J from the result's design to the document's as shown; nullopt
    /// without a result.
    std::optional<double> prediction() const;
    /// A line for people: "Predicted ΔCL/CD = +0.41 (first order, from dJ/dB)" and, after a
    /// confirming solve, the actual change.
    QString predictionText() const;

    /// Solves the flow of the design as shown (Flow > Solve) to confirm the prediction.
    bool confirm(QString* error = nullptr);
    /// The actual change of J from the confirming solve (nullopt until it converged for the
    /// design as shown).
    std::optional<double> confirmedChange() const { return confirmed_; }

  signals:
    void stateChanged(aero::ui::SensitivityRunner::State state);
    /// result() changed (a new one, or dropped).
    void resultChanged();
    void outdatedChanged(bool outdated);
    /// prediction() or confirmedChange() changed.
    void predictionChanged();
    void message(const QString& text, int timeoutMs);

  private:
    void onJobFinished();
    void onDesignChanged();
    void onFlowResult();
    void drop();
    bool matchesDocument() const;

    Document* document_;
    JobRunner* jobs_;
    FlowRunner* flow_;
    QPointer<Job> job_;
    std::shared_ptr<std::shared_ptr<SensitivityResult>> slot_;
    State state_ = State::None;
    QString reason_;
    std::shared_ptr<const SensitivityResult> result_;
    bool outdated_ = false;
    bool confirming_ = false;
    std::optional<double> confirmed_;
    std::vector<ffd::Lattice> confirmedLattices_;  // the design the confirming solve was for
    quint64 generation_ = 0;
    quint64 runGeneration_ = 0;
    std::optional<Objective> chosen_;
};

}  // namespace aero::ui
