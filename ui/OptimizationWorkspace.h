#pragma once
// The optimization workspace of the main window, after the flow workspace's pattern: one run at a
// time (OptimizationRunner) with its panel (OptimizationPanel: the problem, Start / Pause / Stop /
// Resume, the history slider, compare, exports, sensitivities), the live plots
// (OptimizationPlots) and the evaluations in the 3D view (OptimizationScene). The workspace wires
// them together and to the document: problem edits from the panel become undoable document
// edits, the runner's records feed the history, the plots and the slider, the flow reports the
// residual plot, the evaluation chosen (the latest while following the run) goes to the scene.
// While an evaluation takes the 3D view the window hides the document's own geometry, lattices
// and flow solution (viewShownChanged).
//
// GUI thread only; no VTK here (the scene keeps it to itself).
#include <QObject>
#include <QString>
#include <memory>

#include "OptimizationPanel.h"  // Actions (the header has no VTK)
#include "OptimizationRunner.h"
#include "OptimizationScene.h"  // CompareMode (the header has no VTK)

class QWidget;

namespace aero::ui {

class Document;
class JobRunner;
class OptimizationPlots;
class VtkViewport;

class OptimizationWorkspace : public QObject {
    Q_OBJECT

  public:
    OptimizationWorkspace(Document* document, JobRunner* jobs, VtkViewport* viewport,
                          OptimizationScene* scene, QWidget* parentWidget,
                          QObject* parent = nullptr);

    OptimizationRunner& runner() const { return *runner_; }
    OptimizationPanel* panel() const { return panel_; }
    OptimizationPlots* plots() const { return plots_; }
    OptimizationScene& scene() const { return *scene_; }

    /// Optimize > Start: a new run (when a history exists, asks whether to replace it).
    void start();
    /// Optimize > Start Over: asks, then replaces the history with a new run.
    void startOver();
    void pause();
    void stop();
    void resume();

    /// Shows evaluation `index` (from 1) in the 3D view, the panel and the plots (what the
    /// history slider does); 0 shows none.
    void showEvaluation(int index);
    int shownEvaluation() const { return shown_; }
    /// Compares evaluation `index` with the shown one (0: none).
    void compareWith(int index, CompareMode mode);
    /// Whether an evaluation takes the 3D view now: asked for (setViewShown, the panel's "Show in
    /// 3D view") and one to show.
    bool viewShown() const;
    void setViewShown(bool on);

    /// With a file dialog: the shown evaluation's shape, the history, the plots.
    void chooseAndExportShape();
    void chooseAndExportHistory();
    void chooseAndExportPlots();
    /// The shown evaluation's shape as IGES (exact) at `path`; false with *error.
    bool exportShape(const QString& path, QString* error = nullptr) const;
    /// Copies the history (CSV, the iterations' CSV, the JSON lines) to `csvPath` and beside it.
    bool exportHistory(const QString& csvPath, QString* error = nullptr) const;
    /// The shown evaluation's design taken over by the document (one undoable edit).
    bool useShownDesign(QString* error = nullptr);
    /// optimization.start_design = `path` (a case file; empty: the case's own design), one
    /// undoable edit; false with *error (the file, and the variable or value that does not fit)
    /// when the document refuses it. chooseStartDesign() asks for the file.
    bool setStartDesign(const QString& path, QString* error = nullptr);
    void chooseStartDesign();

  signals:
    /// An evaluation took the 3D view or gave it back (the window hides or shows the design's).
    void viewShownChanged(bool shown);
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void showCase();
    void onStateChanged();
    /// A start that could not be made: why, in the panel's state line and the status bar.
    void refuse(const QString& why);
    OptimizationPanel::Actions actions() const;
    void onRecord(const study::OptimizationRecord& r);
    void onHistoryReset();
    void onFlowReport(const FlowRunProgress& p);
    void updateEvaluationPanel();
    void updateSensitivities();
    void applyCompare();
    void applyView();
    QString askPath(const QString& title, const QString& name, const QString& filter) const;

    Document* document_;
    VtkViewport* viewport_;
    OptimizationScene* scene_;
    OptimizationRunner* runner_ = nullptr;
    OptimizationPanel* panel_ = nullptr;
    OptimizationPlots* plots_ = nullptr;
    QWidget* dialogParent_;
    int shown_ = 0;
    int compared_ = 0;
    CompareMode compareMode_ = CompareMode::SideBySide;
    bool newSolve_ = true;
    bool viewWanted_ = false;
    bool lastViewShown_ = false;
};

}  // namespace aero::ui
