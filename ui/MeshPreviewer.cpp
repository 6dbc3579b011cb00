#include "MeshPreviewer.h"

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QEasingCurve>
#include <QFile>
#include <QLocale>
#include <QPointer>
#include <QVariantAnimation>
#include <algorithm>
#include <cmath>

#include "JobRunner.h"
#include "Document.h"
#include "MeshPanel.h"
#include "MeshScene.h"
#include "Text.h"
#include "VtkViewport.h"
#include "common/Error.h"
#include "io/CaseWriter.h"
#include "study/CaseEvaluator.h"

namespace aero::ui {

namespace {

constexpr int kFlightMs = 450;
constexpr std::size_t kMaxMarkedCells = 5000;  // more would only clutter the view

using Vec = std::array<double, 3>;

Vec lerp(const Vec& a, const Vec& b, double t) {
    return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}
double norm(const Vec& a) {
    return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

QString levelName(const std::string& level) {
    QString s = QString::fromStdString(level);
    if (!s.isEmpty()) s[0] = s[0].toUpper();
    return s;
}

QString num(double v) {
    return QLocale().toString(v, 'g', 3);
}

}  // namespace

MeshPreviewer::MeshPreviewer(Document* document, JobRunner* jobs, VtkViewport* viewport,
                             MeshScene* scene, MeshPanel* panel, QObject* parent)
    : QObject(parent),
      document_(document),
      jobs_(jobs),
      viewport_(viewport),
      scene_(scene),
      panel_(panel) {
    flight_ = new QVariantAnimation(this);
    flight_->setDuration(kFlightMs);
    flight_->setStartValue(0.0);
    flight_->setEndValue(1.0);
    flight_->setEasingCurve(QEasingCurve::InOutCubic);

    connect(document_, &Document::shapeChanged, this, &MeshPreviewer::onDocumentChanged);
    connect(document_, &Document::meshOptionsChanged, this, &MeshPreviewer::onDocumentChanged);
    connect(document_, &Document::reset, this, &MeshPreviewer::onReset);
}

// ---- Running ------------------------------------------------------------------------------------

bool MeshPreviewer::start(QString* error) {
    if (!document_->hasGeometry()) {
        if (error) *error = tr("Open a geometry first.");
        return false;
    }
    if (job_) {
        if (error) *error = tr("A mesh preview is running already: wait for it (or cancel it) first.");
        return false;
    }
    // Copies for the worker: it never touches the document.
    auto input = std::make_shared<MeshPreviewInput>();
    input->baseline = document_->baseline();
    input->caseFile = document_->caseFile();
    input->wall = document_->uniquePoints();
    auto slot = std::make_shared<std::shared_ptr<MeshPreviewResult>>();
    clear();
    runningOptions_ = optionsKey();
    pending_.reset();
    QPointer<MeshPreviewer> self(this);
    const quint64 generation = generation_;
    JobSpec<NoProgress> spec;
    spec.title = tr("Mesh preview");
    spec.kind = QStringLiteral("mesh-preview");
    spec.work = [input, slot](const JobContext<NoProgress>& ctx) {
        auto progress = [&ctx](double fraction, const std::string& text) {
            ctx.status(fraction, QString::fromStdString(text));
        };
        *slot = std::make_shared<MeshPreviewResult>(runMeshPreview(*input, progress, ctx.cancelFlag()));
    };
    spec.done = [self, slot, generation] {
        if (self && generation == self->generation_) self->pending_ = *slot;
    };
    job_ = jobs_->start(std::move(spec));
    connect(job_, &Job::progressed, this, [this](double, const QString& text) {
        if (!text.isEmpty()) panel_->setStatus(text);
    });
    connect(job_, &Job::finished, this, &MeshPreviewer::onJobFinished);
    panel_->setRunning(true);
    panel_->setStatus(tr("Starting the %1 grid...").arg(QString::fromStdString(input->caseFile.mesh.level)));
    setState(State::Running);
    return true;
}

void MeshPreviewer::cancel() {
    if (job_) job_->cancel();
}

void MeshPreviewer::onJobFinished() {
    if (!job_) return;
    const bool ok = job_->state() == Job::State::Finished;
    const bool cancelled = job_->state() == Job::State::Cancelled;
    const QString error = job_->error();
    job_ = nullptr;
    panel_->setRunning(false);
    if (ok && pending_) {
        result_ = std::move(pending_);
        pending_.reset();
        resultOptions_ = runningOptions_;
        panel_->setResult(result_);
        if (matchesDocument()) {
            show();
            setState(State::Ready);
            const QString p = problem();
            emit message(
                p.isEmpty() ? tr("Mesh preview: %1, min. Jacobian %2 > 0 (%3 s)")
                                  .arg(description(), num(result_->summary.minJacobian.min),
                                       num(result_->seconds))
                            : p,
                p.isEmpty() ? 10000
                            : 30000);  // a problem also stays in the status bar's problem label
        } else {
            panel_->setOutdated(true);
            panel_->setStatus(
                tr("The geometry or the mesh options changed while the preview ran: run it again."),
                true);
            setState(State::Outdated);
            emit message(
                tr("Mesh preview: the geometry changed while it ran; run it again (Ctrl+M)."),
                10000);
        }
    } else if (ok || cancelled) {  // ok without a result: the document was replaced meanwhile
        panel_->setStatus(tr("Cancelled: no preview."));
        setState(State::Cancelled);
        emit message(tr("Mesh preview cancelled."), 8000);
    } else {
        error_ = error;
        panel_->setStatus(tr("Failed: %1").arg(error), true);
        setState(State::Failed);
        emit message(tr("Mesh preview failed: %1").arg(error), 30000);
    }
}

void MeshPreviewer::show() {
    scene_->setResult(result_);
    std::vector<GridCell> bad;
    for (std::size_t b = 0; b < result_->grids.size() && bad.size() < kMaxMarkedCells; ++b) {
        const mesh::StructuredGrid& g = result_->grids[b];
        const std::vector<double>& jac = result_->quality[b].minJacobian;
        for (int k = 0; k + 1 < g.dims[2] && bad.size() < kMaxMarkedCells; ++k)
            for (int j = 0; j + 1 < g.dims[1]; ++j)
                for (int i = 0; i + 1 < g.dims[0]; ++i)
                    if (!(jac[static_cast<std::size_t>(g.cell(i, j, k))] > 0))
                        bad.push_back({static_cast<int>(b), {i, j, k}});
    }
    scene_->setMarkedCells(bad);
    panel_->setOutdated(false);
    panel_->setStatus(summaryText(), !problem().isEmpty());
    viewport_->requestRender();
}

void MeshPreviewer::clear() {
    flight_->stop();
    scene_->clear();
    result_.reset();
    resultOptions_.clear();
    panel_->setResult(nullptr);
    if (state_ != State::Running) {
        panel_->setStatus(tr("No preview yet."));
        setState(State::None);
    }
    viewport_->requestRender();
}

void MeshPreviewer::setState(State s) {
    if (s == state_) return;
    state_ = s;
    emit stateChanged(s);
}

// ---- Following the document ------------------------------------------------------------------

std::string MeshPreviewer::optionsKey() const {
    io::CaseFile k;
    k.mesh = document_->caseFile().mesh;
    k.mesh.present = true;
    return io::formatCase(k);
}

bool MeshPreviewer::matchesDocument() const {
    return result_ && document_->hasGeometry() && optionsKey() == resultOptions_ &&
           document_->uniquePoints() == result_->wall;
}

void MeshPreviewer::onDocumentChanged() {
    if (state_ == State::Ready && !matchesDocument()) {
        flight_->stop();
        scene_->clear();
        panel_->setOutdated(true);
        panel_->setStatus(tr(
            "Outdated: the geometry or the mesh options changed after this preview. Run it again "
            "(Ctrl+M), or undo to get it back."));
        setState(State::Outdated);
        emit message(tr("The mesh preview is outdated and was taken off the view; run Mesh > "
                        "Preview again."),
                     8000);
        viewport_->requestRender();
    } else if (state_ == State::Outdated && matchesDocument()) {
        show();
        setState(State::Ready);
        emit message(tr("The mesh preview matches the geometry again."), 6000);
    }
}

void MeshPreviewer::onReset() {
    ++generation_;  // a job still running belongs to the previous document
    if (job_) job_->cancel();
    clear();
}

// ---- Reporting --------------------------------------------------------------------------------

QString MeshPreviewer::description() const {
    if (!result_) return {};
    return tr("%1, %2 nodes")
        .arg(counted(static_cast<long long>(result_->grids.size()), tr("block"), tr("blocks")),
             QLocale().toString(static_cast<qlonglong>(result_->gridNodes())));
}

QString MeshPreviewer::problem() const {
    if (state_ != State::Ready || !result_) return {};
    const mesh::QualitySummary& s = result_->summary;
    QStringList parts;
    if (s.nonPositiveJacobian > 0) {
        QString where;
        if (!s.worst.empty()) {
            const mesh::CellLocation& w = s.worst.front();
            where = tr(" (worst: block %1, cell (%2, %3, %4))")
                        .arg(QString::fromStdString(w.blockName))
                        .arg(w.cell[0])
                        .arg(w.cell[1])
                        .arg(w.cell[2]);
        }
        parts << tr("Mesh preview: %1 with a non-positive Jacobian%2, highlighted in red. Use more "
                    "increments or a "
                    "smaller deformation.")
                     .arg(counted(s.nonPositiveJacobian, tr("cell"), tr("cells")), where);
    }
    if (result_->status == MeshPreviewStatus::NotConverged)
        parts << tr("Mesh preview: %1.").arg(QString::fromStdString(result_->message));
    const mesh::WallBend& bend = result_->wallBend;
    if (bend.degrees > study::kWallBendWarning)
        parts << tr("Mesh preview: the wall turns by %1\u00b0 from one grid node to the next at block %2 "
                    "node (%3, %4, %5); the flow there is not resolved and may not converge.")
                     .arg(QString::number(bend.degrees, 'f', 0), QString::fromStdString(bend.blockName))
                     .arg(bend.node[0])
                     .arg(bend.node[1])
                     .arg(bend.node[2]);
    return parts.join(QLatin1Char(' '));
}

QString MeshPreviewer::summaryText() const {
    const MeshPreviewResult& r = *result_;
    const QLocale l;
    QString text =
        tr("%1 grid: %2, %3 control nodes, %4 nodes; ")
            .arg(levelName(r.level),
                 counted(static_cast<long long>(r.grids.size()), tr("block"), tr("blocks")),
                 l.toString(r.mesh.controlCount()),
                 l.toString(static_cast<qlonglong>(r.gridNodes())));
    if (r.moved)
        text += tr("moved in %1 (%2 PCG iterations).")
                    .arg(counted(static_cast<long long>(r.move.cgIterations.size()),
                                 tr("increment"), tr("increments")))
                    .arg(r.move.totalIterations);
    else
        text += tr("the wall is the baseline's (no move).");
    if (r.status == MeshPreviewStatus::NotConverged)
        text += QLatin1Char(' ') + QString::fromStdString(r.message) + QLatin1Char('.');
    text += QLatin1Char(' ') + tr("%1 s.").arg(num(r.seconds));
    return text;
}

// ---- Camera
// ---------------------------------------------------------------------------------------

bool MeshPreviewer::flyToWorstCell(int index) {
    if (state_ != State::Ready || !result_ || index < 0 ||
        index >= static_cast<int>(result_->summary.worst.size()))
        return false;
    const mesh::CellLocation& w = result_->summary.worst[static_cast<std::size_t>(index)];
    const GridCell cell{w.block, w.cell};
    Vec centre{};
    double size = 0;
    if (!scene_->cellCentre(cell, centre, size)) return false;
    scene_->setFocusCell(cell);

    vtkRenderer* ren = viewport_->renderer();
    vtkCamera* cam = ren->GetActiveCamera();
    Vec focal0{}, eye0{};
    cam->GetFocalPoint(focal0.data());
    cam->GetPosition(eye0.data());

    // Same view direction (the user keeps their bearings; the marks are drawn over everything,
    // so the cell shows even behind the body), the cell's centroid as the focal point, from a
    // distance that shows the cell with some of its neighbours.
    const auto b = scene_->wallBounds();
    const double bodySize = std::max(1e-9, std::hypot(b[1] - b[0], b[3] - b[2], b[5] - b[4]));
    const Vec focal1 = w.centroid;
    const Vec view{eye0[0] - focal0[0], eye0[1] - focal0[1], eye0[2] - focal0[2]};
    const double nv = std::max(1e-300, norm(view));
    const double dist = std::max(6 * size, 0.05 * bodySize);
    const Vec eye1{focal1[0] + dist * view[0] / nv, focal1[1] + dist * view[1] / nv,
                   focal1[2] + dist * view[2] / nv};
    flyFocal_ = focal1;

    flight_->stop();
    flight_->disconnect(this);
    auto place = [this, cam, ren](const Vec& focal, const Vec& eye) {
        cam->SetFocalPoint(focal.data());
        cam->SetPosition(eye.data());
        ren->ResetCameraClippingRange();
        viewport_->requestRender();
    };
    connect(flight_, &QVariantAnimation::valueChanged, this, [=](const QVariant& v) {
        const double t = v.toDouble();
        place(lerp(focal0, focal1, t), lerp(eye0, eye1, t));
    });
    connect(flight_, &QVariantAnimation::finished, this, [=] { place(focal1, eye1); });
    flight_->start();
    return true;
}

bool MeshPreviewer::flying() const {
    return flight_->state() == QAbstractAnimation::Running;
}

// ---- Export -------------------------------------------------------------------------------------

void MeshPreviewer::exportGrid(const QString& path) const {
    if (state_ != State::Ready || !result_)
        throw InputError("no current mesh preview to export: run Mesh > Preview first");
    writeGrid(*result_, QFile::encodeName(path).toStdString());
}

}  // namespace aero::ui
