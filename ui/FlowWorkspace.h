#pragma once
// The flow workspace of the main window: one solve at a time (FlowRunner) with its panel
// (FlowPanel: case options, Solve/Stop/Continue, state, forces, display), the live residual plot
// (ResidualPlot), the spanwise sections (SectionView) and the solution in the 3D view
// (FlowScene). The workspace wires them together and to the document: case edits from the panel
// become undoable document edits, the runner's typed reports feed the plot, a new result goes to
// the scene, the panel and the sections, display choices go to the scene. The window places the
// widgets in docks and renders. (The optimization workspace is to follow the same pattern.)
//
// GUI thread only; no VTK here (the scene keeps it to itself).
#include <QObject>
#include <QString>

namespace aero::ui {

class Document;
class FlowPanel;
class FlowRunner;
class FlowScene;
class JobRunner;
class ResidualPlot;
class SectionView;
class VtkViewport;

class FlowWorkspace : public QObject {
    Q_OBJECT

  public:
    FlowWorkspace(Document* document, JobRunner* jobs, VtkViewport* viewport, FlowScene* scene, QWidget* parentWidget,
                  QObject* parent = nullptr);

    FlowRunner& runner() const { return *runner_; }
    FlowPanel* panel() const { return panel_; }
    ResidualPlot* residualPlot() const { return plot_; }
    SectionView* sections() const { return sections_; }
    FlowScene& scene() const { return *scene_; }

    /// Flow > Solve (messages instead of dialogs when it cannot start).
    void solve();
    void stop();
    /// Flow > Continue: a stopped run from its restart file.
    void continueRun();
    /// Whether the solution's wall is drawn in the 3D view (the geometry makes way for it).
    bool wallShown() const;

  signals:
    /// The solution appeared in or left the 3D view (the window re-applies what it hides).
    void solutionShownChanged(bool shown);
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void onStateChanged();
    void onResultChanged();
    void showResult();
    void applyRange();
    void cutSections();
    void fillStations();

    Document* document_;
    VtkViewport* viewport_;
    FlowScene* scene_;
    FlowRunner* runner_ = nullptr;
    FlowPanel* panel_ = nullptr;
    ResidualPlot* plot_ = nullptr;
    SectionView* sections_ = nullptr;
    QWidget* dialogParent_;
    bool shown_ = false;
};

}  // namespace aero::ui
