#pragma once
// Optimize > Start: runs the case's optimization (OptimizationRun.h: study::optimizeCase, as
// `aeroform-cli optimize`) as a job of the JobRunner on a copy of the document's case, one run at
// a time, and keeps what came out in an OptimizationHistory:
//   state     Running; Pausing (asked to pause: it stops after the next whole evaluation or
//             gradient); Paused (at such a boundary); Stopped (by the user or by quitting,
//             within a flow iteration: the evaluation it interrupted is solved again on resume);
//             Finished (the optimizer ended by itself: converged, an iteration or evaluation
//             limit, stalled, infeasible; outcome() says which); Failed (a bad case, a history
//             that belongs to another problem: the reason); Recorded (a history read back from
//             its file, e.g. after the application was closed or crashed);
//   history   every record as it arrives (replayed ones too), each evaluation with its snapshot;
//   flow      the current flow solve's reports, re-emitted for the residual plot.
// Resume continues the history from its file (study::optimizeCase replays it bit for bit, then
// runs on), also in a later session: opening a project whose history exists reads it back.
// The history lives where the case says (optimization.history), by default beside the project:
// an unsaved project cannot be optimized.
//
// GUI thread only; no VTK. The worker never sees the Document.
#include <QObject>
#include <QPointer>
#include <QString>
#include <atomic>
#include <memory>
#include <optional>

#include "FlowRun.h"
#include "OptimizationHistory.h"
#include "OptimizationRun.h"
#include "optimize/Problem.h"

namespace aero::ui {

class Document;
class Job;
class JobRunner;

class OptimizationRunner : public QObject {
    Q_OBJECT

  public:
    enum class State { None, Running, Pausing, Paused, Stopped, Finished, Failed, Recorded };
    /// New: a first run (refused when a history exists); Resume: continue the history; Fresh:
    /// start over, replacing the history.
    enum class Start { New, Resume, Fresh };

    OptimizationRunner(Document* document, JobRunner* jobs, QObject* parent = nullptr);
    ~OptimizationRunner() override;

    /// Starts a run of the document's case. False (with *error) when it cannot: no geometry, no
    /// optimization section, an unsaved project, a run going on, a history that exists (New) or
    /// does not (Resume).
    bool start(Start how, QString* error = nullptr);
    /// Stops after the next whole evaluation or gradient (the history ends on it).
    void pause();
    /// Stops within a flow iteration.
    void stop();
    bool running() const;
    Job* job() const;

    State state() const { return state_; }
    /// One line for people: "Running: evaluation 3 ...", "Paused after evaluation 4 ...".
    QString stateText() const;
    /// Why the run failed, or how the optimizer ended (its message).
    QString reason() const { return reason_; }
    /// How the optimizer ended (Finished, and Paused/Stopped as Cancelled).
    std::optional<optimize::Status> outcome() const { return outcome_; }
    /// The optimizer's summary of the last run that ended (also a paused or stopped one).
    const std::optional<study::OptimizationSummary>& summary() const { return summary_; }

    const OptimizationHistory& history() const { return history_; }
    /// The evaluation being computed (the last recorded + 1) while running, else 0.
    int currentEvaluation() const;
    /// The history file (CSV; the exact JSON lines beside it): the case's optimization.history,
    /// else <project>.history.csv beside the project; empty for an unsaved project.
    QString historyPath() const;
    QString historyJsonlPath() const;
    /// Whether the history's JSON lines exist with at least one record (Resume is possible).
    bool historyExists() const;
    /// Reads the history back (a job: every evaluation's shape stage). False with *error when
    /// there is none or a run is going on.
    bool loadHistory(QString* error = nullptr);
    bool loading() const;

    /// Solves the flow of a recorded evaluation whose solution is not kept (replayed or read
    /// back, or dropped for memory): its design through FlowRun, as Flow > Solve would.
    bool solveEvaluationFlow(int index, QString* error = nullptr);
    bool solvingEvaluation() const;

  signals:
    void stateChanged();
    /// A run started (resumed: the history is continued, not cleared).
    void started(bool resumed);
    /// The history took a record (replayed or new).
    void recordAdded(const aero::study::OptimizationRecord& record);
    /// The history was cleared or read back as a whole.
    void historyReset();
    /// Evaluation `index`'s snapshot changed (its flow solved again, or dropped).
    void snapshotChanged(int index);
    /// A report of the current flow solve (iterations and stage lines).
    void flowReported(const aero::ui::FlowRunProgress& progress);
    /// A line of the optimizer's log.
    void logged(const QString& line);
    void message(const QString& text, int timeoutMs);

  private:
    void setState(State s);
    void onReport(const OptimizationProgress& p);
    void onJobFinished();
    void onLoadFinished(const std::optional<LoadedHistory>& loaded, const QString& error);
    /// Reads the document's history back when it has one and nothing else is going on.
    void loadHistoryOfProject();
    void onReset();
    /// The case as a run sees it: optimization.history resolved, flow present.
    bool runCase(io::CaseFile& c, QString* error) const;

    Document* document_;
    JobRunner* jobs_;
    QPointer<Job> job_, loadJob_, flowJob_;
    struct Slot;
    std::shared_ptr<Slot> slot_;
    std::shared_ptr<std::atomic<bool>> pause_;
    State state_ = State::None;
    QString reason_;
    std::optional<optimize::Status> outcome_;
    std::optional<study::OptimizationSummary> summary_;
    OptimizationHistory history_;
    bool stopRequested_ = false;
    int lastNewEvaluation_ = 0;  // the last evaluation computed (not replayed) by the running job
    quint64 generation_ = 0;     // increases when the document is replaced
    quint64 runGeneration_ = 0;
};

}  // namespace aero::ui
