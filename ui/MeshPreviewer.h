#pragma once
// Mesh > Preview: runs the mesh pipeline (MeshPreview.h) as a job of the JobRunner on a copy of the
// document's state, then shows the result in the MeshScene and the MeshPanel; marks cells with
// a non-positive Jacobian and says so; flies the camera to a worst cell on request; exports the
// grid. The preview follows the document: when the shown geometry or the case's mesh options
// change afterwards, the grid is taken off the view and the panel greyed out ("outdated"); when
// they come back (undo), so does the preview.
//
// GUI thread only. The worker never sees the Document, Qt widgets or VTK objects: it gets
// copies (baseline, mesh options, the wall's control points) and returns a result that is
// read-only from then on (shared by scene and panel).
#include <QObject>
#include <QPointer>
#include <QString>
#include <array>
#include <memory>
#include <string>

#include "MeshPreview.h"

class QVariantAnimation;

namespace aero::ui {

class Job;
class JobRunner;
class Document;
class MeshPanel;
class MeshScene;
class VtkViewport;

class MeshPreviewer : public QObject {
    Q_OBJECT

  public:
    enum class State {
        None,       // no preview (or cleared)
        Running,    // the job runs
        Ready,      // the preview is shown and matches the document
        Outdated,   // the document changed since; the grid is not shown
        Cancelled,  // the last run was cancelled (no preview)
        Failed      // the last run threw (no preview); error() says why
    };

    MeshPreviewer(Document* document, JobRunner* jobs, VtkViewport* viewport, MeshScene* scene,
                  MeshPanel* panel, QObject* parent = nullptr);

    /// Starts a preview of the document as shown. False (with *error) without geometry or while
    /// a preview runs (other jobs, e.g. a flow solve, may run meanwhile).
    bool start(QString* error = nullptr);
    /// Asks the running preview to stop (between elasticity increments).
    void cancel();
    /// Drops the preview (state None).
    void clear();

    State state() const { return state_; }
    std::shared_ptr<const MeshPreviewResult> result() const { return result_; }
    QString error() const { return error_; }
    /// What is wrong with the shown grid, for the status bar (non-positive Jacobians, a move
    /// that did not converge); empty when nothing is or no preview is shown.
    QString problem() const;
    /// "20 blocks, 75,140 nodes" (empty without a result).
    QString description() const;

    /// Flies the camera to worst cell `index` (summary.worst) and highlights it. False for a
    /// bad index or when no preview is shown.
    bool flyToWorstCell(int index);
    /// The camera's destination of the last fly (focal point = the cell's centroid).
    std::array<double, 3> flyTarget() const { return flyFocal_; }
    bool flying() const;

    /// Writes the grid (see writeGrid: .vtm, .xyz, .p3d). Throws aero::Error; InputError when
    /// no current preview exists.
    void exportGrid(const QString& path) const;

  signals:
    void stateChanged(aero::ui::MeshPreviewer::State state);
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void setState(State s);
    void onJobFinished();
    void onDocumentChanged();
    void onReset();
    /// Shows result_ in the scene (with its bad cells marked) and the panel.
    void show();
    bool matchesDocument() const;
    std::string optionsKey() const;
    QString summaryText() const;

    Document* document_;
    JobRunner* jobs_;
    VtkViewport* viewport_;
    MeshScene* scene_;
    MeshPanel* panel_;
    QVariantAnimation* flight_ = nullptr;
    State state_ = State::None;
    std::shared_ptr<const MeshPreviewResult> result_;
    std::shared_ptr<MeshPreviewResult> pending_;  // handed over by the job's `done`
    std::string resultOptions_;                   // optionsKey() the result was made with
    std::string runningOptions_;
    QString error_;
    QPointer<Job> job_;  // the running preview
    quint64 generation_ = 0;  // increases when the document is replaced
    std::array<double, 3> flyFocal_{0, 0, 0};
};

}  // namespace aero::ui
