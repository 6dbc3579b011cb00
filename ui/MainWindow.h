#pragma once
// The desktop application's main window: the VTK viewport in the centre, the model tree and
// the property panel on the left, the design variables and the mesh quality on the right; File
// (open, recent, save, export), Edit (undo/redo), View, FFD and Mesh menus; a status bar that
// explains problems (non-injective lattices, points outside lattices, tangled grid cells) and
// shows background jobs (the mesh preview) with a progress bar and Cancel.
//
// This is the boundary where libcore's exceptions (aero::Error) become messages for the
// user. The state lives in Document; the window wires it to the scenes and panels and
// updates only what changed (shapeChanged -> re-sample those patches in place).
#include <QMainWindow>
#include <QString>
#include <QVector>
#include <array>
#include <functional>
#include <memory>
#include <vector>

class QAction;
class QLabel;
class QMenu;
class QProgressBar;
class QToolButton;

namespace aero::ui {

class Autosaver;
class BackgroundJob;
class DesignVariablePanel;
class Document;
class LatticeEditor;
class LatticeScene;
class MeshPanel;
class MeshPreviewer;
class MeshScene;
class ModelTree;
class OverlayScene;
class PatchScene;
class PropertyPanel;
class Selection;
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

    VtkViewport* viewport() const { return viewport_; }
    PatchScene& scene() const { return *scene_; }
    LatticeScene& latticeScene() const { return *lattices_; }
    OverlayScene& overlayScene() const { return *overlay_; }
    Document& document() const { return *document_; }
    Selection& selection() const { return *selection_; }
    LatticeEditor& latticeEditor() const { return *editor_; }
    DesignVariablePanel& designVariables() const { return *variables_; }
    PropertyPanel& properties() const { return *properties_; }
    ModelTree& modelTree() const { return *tree_; }
    Autosaver* autosaver() const { return autosaver_; }
    BackgroundJob& jobs() const { return *jobs_; }
    MeshScene& meshScene() const { return *meshScene_; }
    MeshPanel& meshPanel() const { return *meshPanel_; }
    MeshPreviewer& meshPreviewer() const { return *previewer_; }
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
    void createMenus();
    void createStatusBar();
    void connectDocument();
    void updateSummary();
    void updateTitle();
    void updateDiagnostics();
    void updateLatticeScene();
    void updateSensitivity();
    void updateActions();
    void onReset();
    void onShapeChanged(const QVector<int>& patches);
    /// Asks to save unsaved changes; false if the user cancelled.
    bool maybeSave();
    bool save();
    bool saveAs();
    void chooseAndOpen();
    void chooseAndSaveScreenshot();
    void exportGeometry();
    void exportVtk();
    void exportGrid();
    void addLattice();
    /// Mesh > Preview: starts the job (messages instead of dialogs when it cannot).
    void startMeshPreview();
    void onMeshPreviewStateChanged();
    /// Grid parts as the model tree's boxes say; the geometry's surfaces make way for the
    /// grid's wall while it is shown (and come back after).
    void applyGridVisibility();
    void addRecentFile(const QString& path);
    void fillRecentMenu();
    /// Runs `work` (which may throw aero::Error) and reports failures in *error.
    bool guarded(const std::function<void()>& work, QString* error);

    Options options_;
    Document* document_ = nullptr;
    Selection* selection_ = nullptr;
    VtkViewport* viewport_ = nullptr;  // central widget, owned by Qt
    std::unique_ptr<PatchScene> scene_;
    std::unique_ptr<LatticeScene> lattices_;
    std::unique_ptr<OverlayScene> overlay_;
    std::unique_ptr<MeshScene> meshScene_;
    MeshPanel* meshPanel_ = nullptr;
    MeshPreviewer* previewer_ = nullptr;
    bool geometryHiddenForGrid_ = false;  // we unchecked Geometry to show the grid's wall
    bool settingGeometry_ = false;
    LatticeEditor* editor_ = nullptr;
    ModelTree* tree_ = nullptr;
    PropertyPanel* properties_ = nullptr;
    DesignVariablePanel* variables_ = nullptr;
    Autosaver* autosaver_ = nullptr;
    BackgroundJob* jobs_ = nullptr;
    QLabel* summaryLabel_ = nullptr;
    QLabel* problemLabel_ = nullptr;
    QProgressBar* jobProgress_ = nullptr;
    QToolButton* jobCancel_ = nullptr;
    QMenu* recentMenu_ = nullptr;
    QAction* saveAction_ = nullptr;
    QAction* latticesAction_ = nullptr;
    QAction* sensitivityAction_ = nullptr;
    QAction* removeLatticeAction_ = nullptr;
    QAction* resetPointsAction_ = nullptr;
    QAction* meshPreviewAction_ = nullptr;
    QAction* meshCancelAction_ = nullptr;
    QAction* meshClearAction_ = nullptr;
    QAction* exportGridAction_ = nullptr;
    std::vector<QAction*> needsGeometry_;
    QString lastDirectory_;
};

}  // namespace aero::ui
