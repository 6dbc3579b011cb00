#pragma once
// Flow > Solve: runs the case's flow solve (FlowRun.h: study::CaseEvaluator's shape, mesh and
// flow stages, as `aeroform-cli flow`) as a job of the JobRunner on a copy of the document's case,
// one solve at a time, and keeps what came out:
//   state        Running, Converged, NotConverged (the solver's reason), Stopped (by the user;
//                the state reached is kept, in a restart file when the project has a place for
//                one), Failed (a bad case, a non-injective lattice, a folded grid: the reason);
//   iterations   every report of the running solve, typed (FlowRunProgress), re-emitted for the
//                residual plot as they arrive;
//   result       the solution with its fields (shared, read-only), also for a run that stopped
//                early (the user sees the state reached).
// The result follows the document like the mesh preview does: when the geometry or the case's
// mesh or flow options change afterwards it is outdated (taken off the 3D view by the
// workspace); when they come back (undo) it is current again.
//
// GUI thread only; no VTK. The worker never sees the Document.
#include <QObject>
#include <QPointer>
#include <QString>
#include <memory>
#include <string>
#include <vector>

#include "FlowRun.h"

namespace aero::ui {

class Document;
class Job;
class JobRunner;

class FlowRunner : public QObject {
    Q_OBJECT

  public:
    enum class State { None, Running, Converged, NotConverged, Stopped, Failed };

    FlowRunner(Document* document, JobRunner* jobs, QObject* parent = nullptr);
    ~FlowRunner() override;

    /// Starts a solve of the document as shown; `continueRun`: from the restart file of a run
    /// that stopped early (restartPath()). False (with *error) without geometry or while a solve
    /// runs (one at a time).
    bool start(QString* error = nullptr, bool continueRun = false);
    /// Asks the running solve to stop (between iterations); the state reached is kept.
    void stop();
    bool running() const;
    /// The running job (null when none), e.g. to wait for it.
    Job* job() const;

    State state() const { return state_; }
    /// One line for people: "Converged in 18 iterations, 4.2 s", "Stopped at iteration 7 ...",
    /// "Failed: ..." (empty for None).
    QString stateText() const;
    /// Why the last run did not converge or failed (empty otherwise).
    QString reason() const { return reason_; }
    std::shared_ptr<const FlowRunResult> result() const { return result_; }
    /// The result no longer matches the document (geometry or mesh/flow options changed).
    bool outdated() const { return outdated_; }
    /// Reports of the current (or last) run, in order.
    const std::vector<FlowRunProgress>& reports() const { return reports_; }
    /// Accepted nonlinear iterations received from the current (or last) run.
    int acceptedIterations() const;

    /// Where a run that stops early keeps its state: output.restart of the case, or
    /// <project>.restart next to the project (as the CLI); empty for an unsaved project.
    QString restartPath() const;
    /// Whether a restart file for this project exists (Continue).
    bool canContinue() const;

    /// Writes the solution as the CLI's flow_vtk (.vtm: density, velocity, pressure, Cp, Mach,
    /// entropy; wall faces). Throws aero::Error; InputError without a solution.
    void exportSolution(const QString& path) const;

  signals:
    void stateChanged(aero::ui::FlowRunner::State state);
    /// A run started: the plots clear.
    void started();
    /// A report of the running solve (typed progress): iterations (hasIteration) and stage lines.
    void reported(const aero::ui::FlowRunProgress& progress);
    /// result() changed (a new solution, or none).
    void resultChanged();
    void outdatedChanged(bool outdated);
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void setState(State s);
    void onReport(const FlowRunProgress& p);
    void onJobFinished();
    void onDocumentChanged();
    void onReset();
    std::string optionsKey() const;
    bool matchesDocument() const;

    Document* document_;
    JobRunner* jobs_;
    QPointer<Job> job_;
    std::shared_ptr<std::shared_ptr<FlowRunResult>> slot_;  // the running job's result
    State state_ = State::None;
    QString reason_;
    std::shared_ptr<const FlowRunResult> result_;
    std::vector<FlowRunProgress> reports_;
    std::string resultOptions_, runningOptions_;
    bool outdated_ = false;
    bool continued_ = false;
    quint64 generation_ = 0;  // increases when the document is replaced
    quint64 runGeneration_ = 0;  // the generation the running job belongs to
};

}  // namespace aero::ui
