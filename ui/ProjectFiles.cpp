#include "ProjectFiles.h"

#include <QDir>
#include <QEventLoop>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QLocale>
#include <QMenu>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QSettings>
#include <QThread>
#include <atomic>
#include <exception>
#include <memory>

#include "Autosave.h"
#include "Document.h"
#include "Resources.h"
#include "cad/OcctProcess.h"
#include "common/Error.h"
#include "io/CaseFile.h"

namespace aero::ui {

namespace {

const char* const kRecentKey = "recentFiles";

int maxRecent() {
    const int n = setting(QStringLiteral("recent/maximum")).toInt();
    return n > 0 ? n : 8;
}

// Document::read on a worker thread while this thread's events run (the window repaints, a
// timer fires). A read that takes more than a moment (OpenCASCADE converting a large or
// damaged CAD file: up to AEROFORM_CAD_TIME_LIMIT) shows a window-modal progress dialog whose
// Cancel stops the helper. Returns what read() returned; throws what it threw (cad::OcctCancelled
// after a cancel).
std::shared_ptr<Document::Loaded> readInBackground(const QString& path, bool project, QWidget* window) {
    std::atomic<bool> cancel{false};
    std::shared_ptr<Document::Loaded> result;
    std::exception_ptr failure;
    std::unique_ptr<QThread> thread(QThread::create([&] {
        const cad::OcctCancelScope scope(&cancel);
        try {
            result = Document::read(path, project);
        } catch (...) {
            failure = std::current_exception();
        }
    }));
    QProgressDialog dialog(QObject::tr("Reading %1 ...").arg(QFileInfo(path).fileName()), QObject::tr("Cancel"), 0, 0,
                           window);
    dialog.setObjectName(QStringLiteral("openProgress"));
    dialog.setWindowTitle(QObject::tr("Opening"));
    dialog.setWindowModality(Qt::WindowModal);
    dialog.setMinimumDuration(400);
    dialog.setAutoClose(false);
    dialog.setAutoReset(false);
    QObject::connect(&dialog, &QProgressDialog::canceled, &dialog, [&] { cancel = true; });
    QEventLoop loop;
    QObject::connect(thread.get(), &QThread::finished, &loop, &QEventLoop::quit, Qt::QueuedConnection);
    thread->start();
    dialog.setValue(0);  // starts the dialog's minimum-duration clock
    loop.exec();
    thread->wait();
    dialog.close();
    if (failure) std::rethrow_exception(failure);
    return result;
}

}  // namespace

ProjectFiles::ProjectFiles(Document* document, QWidget* window, bool recentFiles, QObject* parent)
    : QObject(parent), document_(document), window_(window), recentFiles_(recentFiles) {}

bool ProjectFiles::guarded(const std::function<void()>& work, QString* error) {
    try {
        work();
        return true;
    } catch (const aero::Error& e) {
        if (error) *error = QString::fromStdString(e.what());
    } catch (const std::exception& e) {  // not expected from libcore, but never let it escape
        if (error) *error = tr("Unexpected error: %1").arg(QString::fromStdString(e.what()));
    }
    return false;
}

bool ProjectFiles::supported(const QString& path) {
    const QString s = QFileInfo(path).suffix().toLower();
    return s == QLatin1String("json") || s == QLatin1String("igs") || s == QLatin1String("iges") ||
           s == QLatin1String("stp") || s == QLatin1String("step");
}

// ---- Without dialogs ----------------------------------------------------------------------------

bool ProjectFiles::load(const QString& path, QString* error) {
    const QFileInfo info(path);
    const QString suffix = info.suffix().toLower();
    const std::string file = QFile::encodeName(path).toStdString();
    bool project = false;
    if (suffix == QLatin1String("json")) {
        project = io::looksLikeCase(file);
    } else if (!supported(path)) {
        if (error)
            *error = tr("'%1': unsupported file type (expected a project .json, a patch set .json, .igs, .iges, .stp "
                        "or .step)")
                         .arg(path);
        return false;
    }
    lastLoadCancelled_ = false;
    if (!reading_.isEmpty()) {
        if (error) *error = tr("'%1' is still being read: open another file when it is done").arg(reading_);
        return false;
    }
    reading_ = info.fileName();
    std::shared_ptr<Document::Loaded> loaded;
    const bool ok = guarded(
        [&] {
            try {
                loaded = readInBackground(path, project, window_);
            } catch (const cad::OcctCancelled&) {
                lastLoadCancelled_ = true;  // what the user asked for, not a failure to report
                throw;
            }
        },
        error);
    reading_.clear();
    if (!ok) return false;
    if (!guarded([&] { document_->adoptRead(loaded); }, error)) return false;
    lastDirectory_ = info.absolutePath();
    addRecent(info.absoluteFilePath());
    return true;
}

bool ProjectFiles::loadSample(QString* error, bool withPaperLattice) {
    return guarded([&] { document_->newFromSample(withPaperLattice); }, error);
}

bool ProjectFiles::saveTo(const QString& path, QString* error) {
    if (!guarded([&] { document_->saveProject(path); }, error)) return false;
    lastDirectory_ = QFileInfo(path).absolutePath();
    addRecent(QFileInfo(path).absoluteFilePath());
    emit message(document_->loadMessage().isEmpty() ? tr("Saved %1").arg(path) : document_->loadMessage(), 8000);
    return true;
}

// ---- Interactive ----------------------------------------------------------------------------------

bool ProjectFiles::open(const QString& path) {
    if (!maybeSave()) return false;
    QString error;
    if (load(path, &error)) return true;
    reportOpenFailure(error);
    return false;
}

bool ProjectFiles::openSample(bool withPaperLattice) {
    if (!maybeSave()) return false;
    QString error;
    if (loadSample(&error, withPaperLattice)) return true;
    QMessageBox::critical(window_, tr("Cannot create the sample"), error);
    return false;
}

void ProjectFiles::chooseAndOpen() {
    if (!maybeSave()) return;
    const QString path = QFileDialog::getOpenFileName(
        window_, tr("Open"), lastDirectory_,
        tr("Projects and geometry (*.json *.igs *.iges *.IGS *.IGES *.stp *.step *.STP *.STEP);;Aeroform project or "
           "patch set (*.json);;IGES (*.igs *.iges *.IGS *.IGES);;STEP (*.stp *.step *.STP *.STEP);;All files (*)"));
    if (path.isEmpty()) return;
    QString error;
    if (!load(path, &error)) reportOpenFailure(error);
}

void ProjectFiles::reportOpenFailure(const QString& error) {
    if (lastLoadCancelled_)
        emit message(tr("Opening cancelled: %1").arg(error), 8000);
    else
        QMessageBox::critical(window_, tr("Cannot open file"), error);
}

bool ProjectFiles::maybeSave() {
    if (!document_->isModified()) return true;
    const auto answer = QMessageBox::warning(window_, tr("Unsaved Changes"),
                                             tr("\u201c%1\u201d has unsaved changes. Save them first?").arg(document_->title()),
                                             QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    if (answer == QMessageBox::Save) return save();
    return answer == QMessageBox::Discard;
}

bool ProjectFiles::save() {
    if (document_->projectPath().isEmpty()) return saveAs();
    QString error;
    if (saveTo(document_->projectPath(), &error)) return true;
    QMessageBox::critical(window_, tr("Cannot save"), error);
    return false;
}

bool ProjectFiles::saveAs() {
    QString suggestion = document_->projectPath();
    if (suggestion.isEmpty())
        suggestion = QDir(lastDirectory_.isEmpty() ? QDir::homePath() : lastDirectory_)
                         .filePath(QFileInfo(document_->title()).completeBaseName().replace(QLatin1Char(' '), QLatin1Char('_')) +
                                   QStringLiteral("_project.json"));
    QString path = QFileDialog::getSaveFileName(window_, tr("Save Project"), suggestion, tr("Aeroform project (*.json)"));
    if (path.isEmpty()) return false;
    if (QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".json");
    QString error;
    if (saveTo(path, &error)) return true;
    QMessageBox::critical(window_, tr("Cannot save"), error);
    return false;
}

void ProjectFiles::offerRecovery(Autosaver* autosaver) {
    if (!autosaver) return;
    const auto sessions = Autosaver::findRecoverable(autosaver->directory());
    if (sessions.isEmpty()) return;
    const Autosaver::Recoverable& r = sessions.front();  // the most recent
    QMessageBox box(QMessageBox::Question, tr("Recover Unsaved Work"),
                    tr("Aeroform did not close normally. Unsaved work on \u201c%1\u201d was autosaved at %2.")
                        .arg(r.title.isEmpty() ? tr("an unsaved project") : r.title,
                             QLocale().toString(r.saved, QLocale::ShortFormat)),
                    QMessageBox::NoButton, window_);
    box.setInformativeText(tr("Recover it now? Discard deletes the autosaved copy."));
    QPushButton* recover = box.addButton(tr("Recover"), QMessageBox::AcceptRole);
    QPushButton* discard = box.addButton(tr("Discard"), QMessageBox::DestructiveRole);
    box.addButton(tr("Not Now"), QMessageBox::RejectRole);
    box.setDefaultButton(recover);
    box.exec();
    if (box.clickedButton() == discard) {
        Autosaver::discard(r);
    } else if (box.clickedButton() == recover) {
        QString error;
        if (guarded([&] { document_->recover(r.casePath, r.projectPath, r.generated, r.title); }, &error)) {
            autosaver->saveNow();  // our own session holds it now
            Autosaver::discard(r);
            emit message(tr("Recovered the autosaved work; save it to keep it."), 10000);
        } else {
            QMessageBox::critical(window_, tr("Cannot recover"), error);
        }
    }
}

// ---- Recent files ---------------------------------------------------------------------------------

void ProjectFiles::addRecent(const QString& path) {
    if (!recentFiles_) return;
    QSettings settings;
    QStringList list = settings.value(QLatin1String(kRecentKey)).toStringList();
    list.removeAll(path);
    list.prepend(path);
    while (list.size() > maxRecent()) list.removeLast();
    settings.setValue(QLatin1String(kRecentKey), list);
}

void ProjectFiles::fillRecentMenu(QMenu* menu) {
    menu->clear();
    const QStringList list = recentFiles_ ? QSettings().value(QLatin1String(kRecentKey)).toStringList() : QStringList();
    int n = 0;
    for (const QString& path : list) {
        if (!QFileInfo::exists(path)) continue;
        QAction* a = menu->addAction(QStringLiteral("&%1 %2").arg(++n).arg(QFileInfo(path).fileName()), this,
                                     [this, path] { open(path); });
        a->setToolTip(path);
        a->setStatusTip(path);
    }
    if (n == 0) menu->addAction(tr("(none)"))->setEnabled(false);
    menu->addSeparator();
    menu->addAction(tr("Clear List"), this, [] { QSettings().remove(QLatin1String(kRecentKey)); });
}

}  // namespace aero::ui
