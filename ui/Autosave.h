#pragma once
// Autosave and crash recovery. While the document has unsaved changes, a timer writes it as a
// case file into the autosave folder (default: QStandardPaths::AppDataLocation/autosave),
// together with a generated geometry (the sample) and a small JSON note saying which project
// it belongs to. Each running session holds a lock file; a session that ended without
// cleaning up (a crash) leaves files whose lock is stale: findRecoverable() lists them at the
// next start. A normal exit, a save, or a document without unsaved changes removes them.
//
// Files of a session <base> = <dir>/session-<pid>-<n>:
//   <base>.case.json       the project as a case file (written with io::writeCase)
//   <base>.geometry.json   the baseline geometry, only if it was generated (the sample)
//   <base>.info.json       {"project": path or "", "title": ..., "generated": bool, "saved": ISO time}
//   <base>.lock            QLockFile held while the session runs
// GUI thread only.
#include <QDateTime>
#include <QList>
#include <QObject>
#include <QString>
#include <memory>

class QLockFile;
class QTimer;

namespace aero::ui {

class Document;

class Autosaver : public QObject {
    Q_OBJECT

  public:
    struct Recoverable {
        QString base;         // <dir>/session-...
        QString casePath;     // <base>.case.json
        QString projectPath;  // the project it belongs to (empty: never saved)
        QString title;
        bool generated = false;
        QDateTime saved;
    };

    /// Starts a session in `directory` (created if needed); `intervalMs` between checks.
    Autosaver(Document* document, const QString& directory, int intervalMs = 30000, QObject* parent = nullptr);
    ~Autosaver() override;  // a normal end: removes the session's files

    static QString defaultDirectory();
    /// Sessions in `directory` that ended without cleaning up (their lock is not held).
    static QList<Recoverable> findRecoverable(const QString& directory);
    /// Deletes the files of a recoverable session.
    static void discard(const Recoverable& session);

    void setInterval(int ms);
    /// Writes the document now if it has changes not yet autosaved; true if it wrote.
    bool saveNow();
    /// Removes this session's files (nothing to recover).
    void clear();
    QString casePath() const;
    QString directory() const { return directory_; }

  signals:
    void failed(const QString& message);

  private:
    void tick();

    Document* document_;
    QString directory_;
    QString base_;
    std::unique_ptr<QLockFile> lock_;
    QTimer* timer_ = nullptr;
    quint64 savedRevision_ = 0;
    bool hasFiles_ = false;
};

}  // namespace aero::ui
