#include "Autosave.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLockFile>
#include <QSaveFile>
#include <QStandardPaths>
#include <QTimer>
#include <atomic>

#include "Document.h"
#include "common/Error.h"

namespace aero::ui {

namespace {

std::atomic<int> sessionCounter{0};

QStringList sessionFiles(const QString& base) {
    return {base + QStringLiteral(".case.json"), base + QStringLiteral(".geometry.json"),
            base + QStringLiteral(".info.json")};
}

}  // namespace

Autosaver::Autosaver(Document* document, const QString& directory, int intervalMs, QObject* parent)
    : QObject(parent), document_(document), directory_(directory) {
    QDir().mkpath(directory_);
    base_ = QDir(directory_).filePath(QStringLiteral("session-%1-%2")
                                          .arg(QCoreApplication::applicationPid())
                                          .arg(sessionCounter.fetch_add(1)));
    lock_ = std::make_unique<QLockFile>(base_ + QStringLiteral(".lock"));
    lock_->setStaleLockTime(0);  // stale only when its process is gone
    if (!lock_->tryLock(100)) qWarning("autosave: cannot lock %s", qPrintable(base_));
    timer_ = new QTimer(this);
    timer_->setInterval(intervalMs);
    connect(timer_, &QTimer::timeout, this, &Autosaver::tick);
    timer_->start();
    // A saved (or reverted) document has nothing to recover.
    connect(document_, &Document::modifiedChanged, this, [this](bool modified) {
        if (!modified) clear();
    });
    connect(document_, &Document::reset, this, [this] {
        if (!document_->isModified()) clear();
    });
}

Autosaver::~Autosaver() {
    clear();
    lock_->unlock();
}

QString Autosaver::defaultDirectory() {
    return QDir(QStandardPaths::writableLocation(QStandardPaths::AppDataLocation)).filePath(QStringLiteral("autosave"));
}

QString Autosaver::casePath() const {
    return base_ + QStringLiteral(".case.json");
}

void Autosaver::setInterval(int ms) {
    timer_->setInterval(ms);
}

void Autosaver::tick() {
    if (document_->isModified())
        saveNow();
    else
        clear();
}

bool Autosaver::saveNow() {
    if (!document_->hasGeometry() || !document_->isModified()) return false;
    if (hasFiles_ && savedRevision_ == document_->revision()) return false;
    try {
        document_->writeAutosave(casePath(), base_ + QStringLiteral(".geometry.json"));
    } catch (const aero::Error& e) {
        emit failed(tr("Autosave failed: %1").arg(QString::fromStdString(e.what())));
        return false;
    }
    QJsonObject info;
    info[QStringLiteral("project")] = document_->projectPath();
    info[QStringLiteral("title")] = document_->title();
    info[QStringLiteral("generated")] = document_->geometryGenerated();
    info[QStringLiteral("saved")] = QDateTime::currentDateTime().toString(Qt::ISODate);
    QSaveFile file(base_ + QStringLiteral(".info.json"));
    if (!file.open(QIODevice::WriteOnly) || file.write(QJsonDocument(info).toJson()) < 0 || !file.commit()) {
        emit failed(tr("Autosave failed: cannot write %1").arg(file.fileName()));
        return false;
    }
    if (!document_->geometryGenerated()) QFile::remove(base_ + QStringLiteral(".geometry.json"));
    savedRevision_ = document_->revision();
    hasFiles_ = true;
    return true;
}

void Autosaver::clear() {
    if (!hasFiles_) return;
    for (const QString& f : sessionFiles(base_)) QFile::remove(f);
    hasFiles_ = false;
}

QList<Autosaver::Recoverable> Autosaver::findRecoverable(const QString& directory) {
    QList<Recoverable> out;
    const QDir dir(directory);
    const QStringList infos = dir.entryList({QStringLiteral("session-*.info.json")}, QDir::Files, QDir::Time);
    for (const QString& name : infos) {
        const QString base = dir.filePath(name.left(name.size() - static_cast<int>(qstrlen(".info.json"))));
        QLockFile lock(base + QStringLiteral(".lock"));
        lock.setStaleLockTime(0);
        if (!lock.tryLock(0)) continue;  // its session is still running
        lock.unlock();
        Recoverable r;
        r.base = base;
        r.casePath = base + QStringLiteral(".case.json");
        if (!QFileInfo::exists(r.casePath)) continue;
        QFile f(base + QStringLiteral(".info.json"));
        if (f.open(QIODevice::ReadOnly)) {
            const QJsonObject info = QJsonDocument::fromJson(f.readAll()).object();
            r.projectPath = info.value(QStringLiteral("project")).toString();
            r.title = info.value(QStringLiteral("title")).toString();
            r.generated = info.value(QStringLiteral("generated")).toBool();
            r.saved = QDateTime::fromString(info.value(QStringLiteral("saved")).toString(), Qt::ISODate);
        }
        out.push_back(r);
    }
    return out;
}

void Autosaver::discard(const Recoverable& session) {
    for (const QString& f : sessionFiles(session.base)) QFile::remove(f);
    QFile::remove(session.base + QStringLiteral(".lock"));
}

}  // namespace aero::ui
