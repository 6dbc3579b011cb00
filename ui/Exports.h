#pragma once
// File > Export: the deformed geometry (IGES, JSON), the geometry for ParaView (VTK), the
// previewed grid (VTK with quality fields, Plot3D), the flow solution (VTK) and screenshots, each
// behind a file dialog; failures in message boxes, successes in the status bar. The writing
// itself is libcore's (or the previewer's and the flow runner's, which call libcore). GUI thread
// only; no VTK.
#include <QObject>
#include <QString>
#include <functional>

class QWidget;

namespace aero::ui {

class Document;
class FlowRunner;
class MeshPreviewer;
class ProjectFiles;

class Exports : public QObject {
    Q_OBJECT

  public:
    /// `screenshot` writes the 3D view to a path (false with *error); `problems` describes what
    /// is wrong with the current state (empty when nothing is).
    Exports(Document* document, ProjectFiles* files, MeshPreviewer* previewer, FlowRunner* flow, QWidget* window,
            std::function<bool(const QString&, QString*)> screenshot, std::function<QString()> problems,
            QObject* parent = nullptr);

    void exportGeometry();
    void exportVtk();
    void exportGrid();
    void exportFlow();
    void saveScreenshot();

  signals:
    void message(const QString& text, int timeoutMs);

  private:
    /// A save dialog starting in the last folder.
    QString askPath(const QString& title, const QString& filters, QString* filter = nullptr) const;
    void report(bool ok, const QString& path, const QString& failureTitle, const QString& error);

    Document* document_;
    ProjectFiles* files_;
    MeshPreviewer* previewer_;
    FlowRunner* flow_;
    QWidget* window_;
    std::function<bool(const QString&, QString*)> screenshot_;
    std::function<QString()> problems_;
};

}  // namespace aero::ui
