#pragma once
// The desktop application's main window: the VTK viewport in the centre, the model tree and
// the property panel on the left, the design variables, the mesh quality, the flow and the
// optimization panels on the right, the residual history, the spanwise sections and the
// optimization's plots below; menus and a tool bar of typed actions (ActionSet, Menus); a status
// bar that explains problems (non-injective lattices, points outside lattices, tangled grid
// cells) and shows the running background jobs (JobStatusBar).
//
// The window assembles the parts and keeps the 3D view in step with the document (shapeChanged
// -> re-sample those patches in place). Its other concerns live in their own files: project files
// (ProjectFiles), exports (Exports), the mesh preview (MeshPreviewer), the flow solve and its
// plots (FlowWorkspace), the optimization (OptimizationWorkspace), the design sensitivities
// (SensitivityWorkspace), background work (JobRunner).
// Quitting while a job runs asks first, then stops and waits for it.
#include <QMainWindow>
#include <QString>
#include <QVector>
#include <array>
#include <memory>

class QLabel;

namespace aero::ui {

struct ActionSet;
struct MenuRefs;
class Autosaver;
class DesignVariablePanel;
class Document;
class Exports;
class FlowScene;
class FlowWorkspace;
class JobRunner;
class JobStatusBar;
class LatticeEditor;
class LatticeScene;
class MeshPanel;
class MeshPreviewer;
class MeshScene;
class ModelTree;
class OptimizationScene;
class OptimizationWorkspace;
class OverlayScene;
class PatchScene;
class ProjectFiles;
class PropertyPanel;
class Selection;
class SensitivityRunner;
class SensitivityWorkspace;
class SurfaceFieldScene;
class VtkViewport;

class MainWindow : public QMainWindow {
    Q_OBJECT

  public:
    struct Options {
        bool autosave = true;       // autosave into autosaveDirectory (default location if empty)
        QString autosaveDirectory;
        int autosaveIntervalMs = 30000;
        bool recentFiles = true;    // remember opened files (QSettings)
    };
    /// The options of an interactive session (autosave interval from the settings).
    static Options defaultOptions();

    explicit MainWindow(QWidget* parent = nullptr);
    explicit MainWindow(const Options& options, QWidget* parent = nullptr);
    ~MainWindow() override;

    /// Opens a project (case file), a patch set (.json) or IGES (.igs/.iges). No dialogs: on
    /// failure returns false, leaves everything as it was and sets *error (if given). Does
    /// not ask about unsaved changes (see openFile).
    bool loadFile(const QString& path, QString* error = nullptr);
    /// The paper's half-sphere sample; with its 6x6x2 FFD lattice and 89 design variables, or
    /// the geometry alone.
    bool loadSample(QString* error = nullptr, bool withPaperLattice = true);
    /// Saves the project (a case file). No dialogs.
    bool saveProject(const QString& path, QString* error = nullptr);

    /// Interactive variants: ask about unsaved changes, show failures in a message box.
    bool openFile(const QString& path);
    bool openSample(bool withPaperLattice = true);
    /// Offers to recover autosaved work of a session that ended unexpectedly.
    void offerRecovery();

    /// Writes the viewport's current frame (format from the suffix, e.g. .png).
    bool saveScreenshot(const QString& path, QString* error = nullptr);

    /// The default view: oblique from upstream, above and the +Y side; X streamwise, Z up.
    void resetCamera();
    /// Looks along `direction` with `up` at the whole model.
    void setView(const std::array<double, 3>& direction, const std::array<double, 3>& up);

    const ActionSet& actions() const { return *actions_; }
    VtkViewport* viewport() const { return viewport_; }
    PatchScene& scene() const { return *scene_; }
    LatticeScene& latticeScene() const { return *lattices_; }
    OverlayScene& overlayScene() const { return *overlay_; }
    /// The arrows dJ/dB at the lattice points (after Flow > Compute Sensitivities).
    OverlayScene& gradientScene() const { return *gradientArrows_; }
    SensitivityRunner& sensitivities() const { return *sensitivities_; }
    SensitivityWorkspace& sensitivity() const { return *sensitivity_; }
    /// The surface sensitivity dJ/dA . n on the wall (View > Surface Sensitivity).
    SurfaceFieldScene& surfaceSensitivityScene() const { return *surfaceField_; }
    Document& document() const { return *document_; }
    Selection& selection() const { return *selection_; }
    LatticeEditor& latticeEditor() const { return *editor_; }
    DesignVariablePanel& designVariables() const { return *variables_; }
    PropertyPanel& properties() const { return *properties_; }
    ModelTree& modelTree() const { return *tree_; }
    Autosaver* autosaver() const { return autosaver_; }
    JobRunner& jobs() const { return *jobs_; }
    MeshScene& meshScene() const { return *meshScene_; }
    MeshPanel& meshPanel() const { return *meshPanel_; }
    MeshPreviewer& meshPreviewer() const { return *previewer_; }
    FlowScene& flowScene() const { return *flowScene_; }
    FlowWorkspace& flow() const { return *flow_; }
    OptimizationScene& optimizationScene() const { return *optimizationScene_; }
    OptimizationWorkspace& optimization() const { return *optimization_; }
    ProjectFiles& files() const { return *files_; }
    /// "20 patches, 720 control points", or "No geometry".
    QString summary() const;
    /// The problem text shown in the status bar (empty when all is well).
    QString problemText() const;

  protected:
    void closeEvent(QCloseEvent* e) override;
    void dragEnterEvent(QDragEnterEvent* e) override;
    void dropEvent(QDropEvent* e) override;

  private:
    void createDocks();
    void createStatusBar();
    void connectActions();
    void connectDocument();
    void updateSummary();
    void updateTitle();
    void updateDiagnostics();
    void updateLatticeScene();
    void updateActions();
    void onReset();
    void onShapeChanged(const QVector<int>& patches);
    /// Mesh > Preview: starts the job (messages instead of dialogs when it cannot).
    void startMeshPreview();
    void onMeshPreviewStateChanged();
    void startFlowSolve(bool continueRun);
    /// An optimization's evaluation took the 3D view or gave it back: the design's own
    /// geometry, lattices and flow solution make way for it, and come back.
    void applyOptimizationView();
    /// Grid parts as the model tree's boxes say; the geometry's surfaces make way for the
    /// grid's or the flow solution's wall while one is shown (and come back after).
    void applyResultVisibility();
    void selectAllLatticePoints();
    void addLattice();
    /// Asks before quitting while jobs run; then stops them and waits. False: keep running.
    bool confirmQuitWhileWorking();

    Options options_;
    std::unique_ptr<ActionSet> actions_;
    std::unique_ptr<MenuRefs> menus_;
    Document* document_ = nullptr;
    Selection* selection_ = nullptr;
    JobRunner* jobs_ = nullptr;
    VtkViewport* viewport_ = nullptr;  // central widget, owned by Qt
    std::unique_ptr<PatchScene> scene_;
    std::unique_ptr<LatticeScene> lattices_;
    std::unique_ptr<OverlayScene> overlay_;
    std::unique_ptr<OverlayScene> gradientArrows_;
    std::unique_ptr<SurfaceFieldScene> surfaceField_;
    std::unique_ptr<MeshScene> meshScene_;
    std::unique_ptr<FlowScene> flowScene_;
    std::unique_ptr<OptimizationScene> optimizationScene_;
    MeshPanel* meshPanel_ = nullptr;
    MeshPreviewer* previewer_ = nullptr;
    FlowWorkspace* flow_ = nullptr;
    OptimizationWorkspace* optimization_ = nullptr;
    SensitivityRunner* sensitivities_ = nullptr;
    SensitivityWorkspace* sensitivity_ = nullptr;  // shows the runner's result (and dS/dv)
    QLabel* predictionLabel_ = nullptr;
    ProjectFiles* files_ = nullptr;
    Exports* exports_ = nullptr;
    bool geometryHiddenForResults_ = false;  // we unchecked Geometry to show a result's wall
    bool settingGeometry_ = false;
    LatticeEditor* editor_ = nullptr;
    ModelTree* tree_ = nullptr;
    PropertyPanel* properties_ = nullptr;
    DesignVariablePanel* variables_ = nullptr;
    Autosaver* autosaver_ = nullptr;
    JobStatusBar* jobStatus_ = nullptr;
    QLabel* summaryLabel_ = nullptr;
    QLabel* problemLabel_ = nullptr;
};

}  // namespace aero::ui
