#pragma once
// The project's files, for the main window: open (project case files, patch sets, IGES, the
// sample), save and save as, the recent-files list, drag and drop, and the recovery of autosaved
// work after a crash. The non-interactive variants report failures through *error (no dialogs:
// tests and --screenshot use them); the interactive ones ask about unsaved changes and show
// failures in message boxes. This is where libcore's exceptions (aero::Error) from loading and
// saving become messages. GUI thread only; no VTK.
#include <QObject>
#include <QString>
#include <functional>

class QMenu;
class QWidget;

namespace aero::ui {

class Autosaver;
class Document;

class ProjectFiles : public QObject {
    Q_OBJECT

  public:
    /// `window`: the parent of dialogs. `recentFiles`: remember opened files (QSettings).
    ProjectFiles(Document* document, QWidget* window, bool recentFiles, QObject* parent = nullptr);

    /// Opens a project (case file), a patch set (.json), IGES or STEP. The files are read on a
    /// worker thread while the window stays live; a read that takes longer than a moment shows a
    /// progress dialog whose Cancel stops it (OpenCASCADE's helper is killed: cad::OcctCancelScope).
    /// No other dialogs. On failure or cancel returns false, leaves everything as it was and sets
    /// *error (if given); lastLoadCancelled() tells a cancel from a failure.
    bool load(const QString& path, QString* error = nullptr);
    bool lastLoadCancelled() const { return lastLoadCancelled_; }
    bool loadSample(QString* error = nullptr, bool withPaperLattice = true);
    bool saveTo(const QString& path, QString* error = nullptr);

    /// Interactive: ask about unsaved changes, show failures in a message box.
    bool open(const QString& path);
    bool openSample(bool withPaperLattice = true);
    void chooseAndOpen();
    /// Asks to save unsaved changes; false if the user cancelled.
    bool maybeSave();
    bool save();
    bool saveAs();
    /// Offers to recover autosaved work of a session that ended unexpectedly.
    void offerRecovery(Autosaver* autosaver);

    /// Fills `menu` with the recent files (call when it is about to show).
    void fillRecentMenu(QMenu* menu);
    /// Whether `path` has a suffix the application opens (for drops).
    static bool supported(const QString& path);

    /// The folder of the last file opened or saved (dialogs start there).
    QString lastDirectory() const { return lastDirectory_; }
    void setLastDirectory(const QString& dir) { lastDirectory_ = dir; }

    /// Runs `work` (which may throw aero::Error) and reports failures in *error.
    static bool guarded(const std::function<void()>& work, QString* error);

  signals:
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void addRecent(const QString& path);
    /// After a failed interactive open: a message box, or a status message after a cancel.
    void reportOpenFailure(const QString& error);

    Document* document_;
    QWidget* window_;
    bool recentFiles_;
    QString lastDirectory_;
    QString reading_;                 // the file being read (load() refuses a second one meanwhile)
    bool lastLoadCancelled_ = false;
};

}  // namespace aero::ui
