#include "Exports.h"

#include <QApplication>
#include <QFileDialog>
#include <QFileInfo>
#include <QMessageBox>

#include "Document.h"
#include "FlowRunner.h"
#include "MeshPreviewer.h"
#include "ProjectFiles.h"

namespace aero::ui {

Exports::Exports(Document* document, ProjectFiles* files, MeshPreviewer* previewer, FlowRunner* flow, QWidget* window,
                 std::function<bool(const QString&, QString*)> screenshot, std::function<QString()> problems,
                 QObject* parent)
    : QObject(parent),
      document_(document),
      files_(files),
      previewer_(previewer),
      flow_(flow),
      window_(window),
      screenshot_(std::move(screenshot)),
      problems_(std::move(problems)) {}

QString Exports::askPath(const QString& title, const QString& filters, QString* filter) const {
    return QFileDialog::getSaveFileName(window_, title, files_->lastDirectory(), filters, filter);
}

void Exports::report(bool ok, const QString& path, const QString& failureTitle, const QString& error) {
    if (ok)
        emit message(tr("Exported %1").arg(path), 5000);
    else
        QMessageBox::critical(window_, failureTitle, error);
}

void Exports::exportGeometry() {
    const QString problems = problems_ ? problems_() : QString();
    if (!problems.isEmpty()) {
        const auto answer =
            QMessageBox::warning(window_, tr("Export Deformed Geometry"),
                                 tr("The current state has problems:\n\n%1\n\nExport anyway?").arg(problems),
                                 QMessageBox::Yes | QMessageBox::Cancel, QMessageBox::Cancel);
        if (answer != QMessageBox::Yes) return;
    }
    const QString path = askPath(tr("Export Deformed Geometry"), tr("IGES (*.igs *.iges);;STEP (*.stp *.step);;Aeroform patch set (*.json)"));
    if (path.isEmpty()) return;
    QString error;
    const bool ok = ProjectFiles::guarded([&] { document_->exportGeometry(path); }, &error);
    report(ok, path, tr("Cannot export"), error);
}

void Exports::exportVtk() {
    QString path = askPath(tr("Export for ParaView"), tr("VTK multiblock (*.vtm)"));
    if (path.isEmpty()) return;
    if (QFileInfo(path).suffix().toLower() != QLatin1String("vtm")) path += QStringLiteral(".vtm");
    QString error;
    const bool ok = ProjectFiles::guarded([&] { document_->exportVtk(path); }, &error);
    report(ok, path, tr("Cannot export"), error);
}

void Exports::exportGrid() {
    QString filter;
    QString path = askPath(tr("Export Grid"),
                           tr("VTK multiblock with quality fields (*.vtm);;Plot3D binary (*.xyz);;Plot3D ASCII (*.p3d)"), &filter);
    if (path.isEmpty()) return;
    if (QFileInfo(path).suffix().isEmpty())
        path += filter.contains(QLatin1String("*.xyz"))   ? QStringLiteral(".xyz")
                : filter.contains(QLatin1String("*.p3d")) ? QStringLiteral(".p3d")
                                                          : QStringLiteral(".vtm");
    QString error;
    QApplication::setOverrideCursor(Qt::WaitCursor);
    const bool ok = ProjectFiles::guarded([&] { previewer_->exportGrid(path); }, &error);
    QApplication::restoreOverrideCursor();
    report(ok, path, tr("Cannot export the grid"), error);
}

void Exports::exportFlow() {
    QString path = askPath(tr("Export Flow Solution"), tr("VTK multiblock (*.vtm)"));
    if (path.isEmpty()) return;
    if (QFileInfo(path).suffix().toLower() != QLatin1String("vtm")) path += QStringLiteral(".vtm");
    QString error;
    QApplication::setOverrideCursor(Qt::WaitCursor);
    const bool ok = ProjectFiles::guarded([&] { flow_->exportSolution(path); }, &error);
    QApplication::restoreOverrideCursor();
    report(ok, path, tr("Cannot export the flow solution"), error);
}

void Exports::saveScreenshot() {
    const QString path = askPath(tr("Save Screenshot"), tr("PNG image (*.png);;JPEG image (*.jpg *.jpeg)"));
    if (path.isEmpty()) return;
    QString error;
    if (screenshot_(path, &error))
        emit message(tr("Saved %1").arg(path), 5000);
    else
        QMessageBox::critical(window_, tr("Cannot save screenshot"), error);
}

}  // namespace aero::ui
