#pragma once
// The desktop application's main window: a VTK viewport showing a patch set, File and View
// menus, and a status bar with "N patches, M control points". This is the boundary where
// libcore's exceptions (aero::Error) become messages for the user.
#include <QMainWindow>
#include <QString>
#include <functional>
#include <memory>

class QAction;
class QLabel;

namespace aero::geometry {
struct PatchSet;
}

namespace aero::ui {

class PatchScene;
class VtkViewport;

class MainWindow : public QMainWindow {
    Q_OBJECT

  public:
    explicit MainWindow(QWidget* parent = nullptr);
    ~MainWindow() override;

    /// Loads a patch set (.json native format, .igs/.iges) and shows it. No dialogs: on
    /// failure returns false, leaves the current scene as it was and sets *error (if given).
    bool loadFile(const QString& path, QString* error = nullptr);
    /// Shows the paper's half-sphere sample (20 patches).
    bool loadSample(QString* error = nullptr);

    /// Interactive variants: failures are shown in a message box.
    bool openFile(const QString& path);
    bool openSample();

    /// Writes the viewport's current frame (format from the suffix, e.g. .png).
    bool saveScreenshot(const QString& path, QString* error = nullptr);

    /// The default view: oblique from upstream, above and the +Y side; X streamwise, Z up.
    void resetCamera();

    VtkViewport* viewport() const { return viewport_; }
    PatchScene& scene() const { return *scene_; }
    /// "20 patches, 720 control points", or "No geometry".
    QString summary() const;

  private:
    void createMenus();
    void updateSummary();
    /// Runs `read`, shows its result titled `title`; catches libcore's errors into *error.
    bool load(const std::function<geometry::PatchSet()>& read, const QString& title,
              QString* error);
    void chooseAndOpen();
    void chooseAndSaveScreenshot();

    VtkViewport* viewport_ = nullptr;  // central widget, owned by Qt
    std::unique_ptr<PatchScene> scene_;
    QLabel* summaryLabel_ = nullptr;
    QString lastDirectory_;
};

}  // namespace aero::ui
