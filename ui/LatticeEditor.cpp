#include "LatticeEditor.h"

#include <QCursor>
#include <QKeyEvent>
#include <QMouseEvent>
#include <cmath>
#include <limits>
#include <numeric>

#include "Document.h"
#include "LatticeScene.h"
#include "Selection.h"
#include "Text.h"
#include "VtkViewport.h"
#include "common/Error.h"

namespace aero::ui {

namespace {

using V3 = std::array<double, 3>;

double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V3 sub(const V3& a, const V3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V3 axpy(double s, const V3& x, const V3& y) {
    return {y[0] + s * x[0], y[1] + s * x[1], y[2] + s * x[2]};
}
V3 unit(int axis) {
    V3 e{0, 0, 0};
    e[static_cast<std::size_t>(axis)] = 1;
    return e;
}

// Intersection of the ray (o, d) with the plane through p with normal n; false if parallel.
bool rayPlane(const V3& o, const V3& d, const V3& p, const V3& n, V3& hit) {
    const double den = dot(d, n);
    if (std::abs(den) < 1e-12) return false;
    hit = axpy(dot(sub(p, o), n) / den, d, o);
    return true;
}

// Parameter s of the point p + s e closest to the ray (o, d) (e, d unit); false if parallel.
bool lineRayParameter(const V3& p, const V3& e, const V3& o, const V3& d, double& s) {
    const V3 w = sub(p, o);
    const double b = dot(e, d), denom = 1 - b * b;
    if (denom < 1e-9) return false;
    s = (b * dot(d, w) - dot(e, w)) / denom;
    return true;
}

constexpr double kStartDistance = 3.0;  // pixels before a press on a point becomes a drag
const char* const kAxisNames[] = {"X", "Y", "Z"};

}  // namespace

LatticeEditor::LatticeEditor(VtkViewport* viewport, Document* document, Selection* selection,
                             const LatticeScene* scene, QObject* parent)
    : QObject(parent), viewport_(viewport), document_(document), selection_(selection), scene_(scene) {
    viewport_->installEventFilter(this);
}

LatticeEditor::Hit LatticeEditor::pointAt(const QPointF& pos) const {
    Hit best;
    double bestDist = pickRadius();
    double bestDepth = std::numeric_limits<double>::max();
    const auto& lattices = document_->lattices();
    for (int l = 0; l < static_cast<int>(lattices.size()); ++l) {
        if (!scene_->latticeVisible(l)) continue;
        const ffd::Lattice& L = lattices[static_cast<std::size_t>(l)];
        for (int a = 0; a < L.controlCount(); ++a) {
            const double* x = &L.points[3 * static_cast<std::size_t>(a)];
            QPointF w;
            double depth = 0;
            if (!viewport_->project({x[0], x[1], x[2]}, &w, &depth)) continue;
            const double dist = std::hypot(w.x() - pos.x(), w.y() - pos.y());
            // Nearest on screen; among (nearly) coincident ones, the one closest to the viewer.
            if (dist < bestDist - 0.5 || (dist <= bestDist + 0.5 && depth < bestDepth && dist <= pickRadius())) {
                best = Hit{l, a};
                bestDist = std::min(bestDist, dist);
                bestDepth = depth;
            }
        }
    }
    return best;
}

bool LatticeEditor::eventFilter(QObject* watched, QEvent* event) {
    if (watched != viewport_) return false;
    switch (event->type()) {
        case QEvent::MouseButtonPress:
        case QEvent::MouseButtonDblClick:
            return press(static_cast<QMouseEvent*>(event));
        case QEvent::MouseMove:
            return move(static_cast<QMouseEvent*>(event));
        case QEvent::MouseButtonRelease:
            return release(static_cast<QMouseEvent*>(event));
        case QEvent::KeyPress: {
            auto* k = static_cast<QKeyEvent*>(event);
            if (k->key() == Qt::Key_Escape) {
                if (drag_.active) {
                    cancelDrag();
                } else if (selection_->kind() == Selection::Kind::LatticePoints) {
                    selection_->selectLattice(selection_->lattice());
                }
                return true;
            }
            if (k->matches(QKeySequence::SelectAll)) {
                int l = selection_->lattice();
                if (l < 0 && !document_->lattices().empty()) l = 0;
                if (l >= 0 && l < static_cast<int>(document_->lattices().size())) {
                    std::vector<int> all(static_cast<std::size_t>(document_->lattices()[static_cast<std::size_t>(l)].controlCount()));
                    std::iota(all.begin(), all.end(), 0);
                    selection_->selectPoints(l, std::move(all));
                }
                return true;
            }
            if (drag_.active && k->key() == Qt::Key_Shift && drag_.moved) {
                // Switching constraint mid-drag: re-evaluate at the current cursor.
                const QPointF pos = viewport_->mapFromGlobal(QCursor::pos());
                drag_.axis = -1;
                drag_.delta = dragDelta(pos, true);
                document_->previewLatticeMove(drag_.lattice, drag_.points, drag_.delta);
                viewport_->requestRender();
                return true;
            }
            return false;
        }
        default:
            return false;
    }
}

bool LatticeEditor::press(QMouseEvent* e) {
    emptyPress_ = QPointF(-1, -1);
    if (e->button() != Qt::LeftButton) return drag_.active;  // other buttons mid-drag: swallow
    const Hit hit = pointAt(e->position());
    if (!hit) {
        emptyPress_ = e->position();
        return false;  // the camera's
    }
    viewport_->setFocus(Qt::MouseFocusReason);
    if (e->modifiers() & Qt::ControlModifier) {
        selection_->togglePoint(hit.lattice, hit.point);
        return true;
    }
    if (!selection_->hasPoint(hit.lattice, hit.point)) selection_->selectPoints(hit.lattice, {hit.point});
    drag_ = Drag{};
    drag_.active = true;
    drag_.lattice = hit.lattice;
    drag_.points = selection_->points();
    drag_.pressPos = e->position();
    const double* x = &document_->lattices()[static_cast<std::size_t>(hit.lattice)].points[3 * static_cast<std::size_t>(hit.point)];
    drag_.grabbed = {x[0], x[1], x[2]};
    drag_.normal = viewport_->viewDirection();
    V3 o, d;
    viewport_->pickRay(e->position(), o, d);
    if (!rayPlane(o, d, drag_.grabbed, drag_.normal, drag_.start)) drag_.start = drag_.grabbed;
    viewport_->setCursor(Qt::ClosedHandCursor);
    return true;
}

int LatticeEditor::chooseAxis(const QPointF& pos) const {
    const QPointF drag = pos - drag_.pressPos;
    const double dragLen = std::hypot(drag.x(), drag.y());
    QPointF origin;
    if (dragLen < 1e-9 || !viewport_->project(drag_.grabbed, &origin)) return -1;
    // Screen direction of each world axis at the grabbed point; the best aligned one wins.
    // Axes nearly along the line of sight (short on screen) are not eligible.
    const auto& L = document_->lattices()[static_cast<std::size_t>(drag_.lattice)];
    double extent = 0;
    for (std::size_t k = 0; k + 2 < L.points.size(); k += 3)
        for (int c = 0; c < 3; ++c)
            extent = std::max(extent, std::abs(L.points[k + static_cast<std::size_t>(c)] - drag_.grabbed[static_cast<std::size_t>(c)]));
    const double probe = std::max(extent, 1e-6) * 0.1;
    int best = -1;
    double bestScore = -1;
    for (int axis = 0; axis < 3; ++axis) {
        QPointF tip;
        if (!viewport_->project(axpy(probe, unit(axis), drag_.grabbed), &tip)) continue;
        const QPointF s = tip - origin;
        const double len = std::hypot(s.x(), s.y());
        if (len < 2.0) continue;
        const double score = std::abs(s.x() * drag.x() + s.y() * drag.y()) / (len * dragLen);
        if (score > bestScore) {
            bestScore = score;
            best = axis;
        }
    }
    return best;
}

std::array<double, 3> LatticeEditor::dragDelta(const QPointF& pos, bool alongAxis) {
    V3 o, d;
    viewport_->pickRay(pos, o, d);
    if (alongAxis) {
        if (drag_.axis < 0) drag_.axis = chooseAxis(pos);
        if (drag_.axis >= 0) {
            const V3 e = unit(drag_.axis);
            V3 o0, d0;
            viewport_->pickRay(drag_.pressPos, o0, d0);
            double s = 0, s0 = 0;
            if (lineRayParameter(drag_.grabbed, e, o, d, s) && lineRayParameter(drag_.grabbed, e, o0, d0, s0))
                return {(s - s0) * e[0], (s - s0) * e[1], (s - s0) * e[2]};
            return drag_.delta;
        }
    } else {
        drag_.axis = -1;
    }
    V3 hit;
    if (!rayPlane(o, d, drag_.grabbed, drag_.normal, hit)) return drag_.delta;
    return sub(hit, drag_.start);
}

bool LatticeEditor::move(QMouseEvent* e) {
    if (!drag_.active) {
        if (e->buttons() == Qt::NoButton) {
            // Hover feedback: an open hand over a point that can be grabbed.
            if (pointAt(e->position()))
                viewport_->setCursor(Qt::OpenHandCursor);
            else if (viewport_->cursor().shape() == Qt::OpenHandCursor)
                viewport_->setCursor(Qt::ArrowCursor);
        }
        return false;
    }
    if (drag_.cancelled) return true;
    const QPointF step = e->position() - drag_.pressPos;
    if (!drag_.moved && std::hypot(step.x(), step.y()) < kStartDistance) return true;
    drag_.moved = true;
    const bool alongAxis = (e->modifiers() & Qt::ShiftModifier) != 0;
    drag_.delta = dragDelta(e->position(), alongAxis);
    document_->previewLatticeMove(drag_.lattice, drag_.points, drag_.delta);
    viewport_->requestRender();
    const auto& d = drag_.delta;
    QString text = tr("Moving %4 by (%1, %2, %3)")
                       .arg(d[0], 0, 'f', 4)
                       .arg(d[1], 0, 'f', 4)
                       .arg(d[2], 0, 'f', 4)
                       .arg(counted(static_cast<long long>(drag_.points.size()), tr("point"), tr("points")));
    if (alongAxis && drag_.axis >= 0)
        text += tr(" along %1").arg(QLatin1String(kAxisNames[drag_.axis]));
    else
        text += tr(" in the view plane (hold Shift to move along an axis, Esc cancels)");
    emit message(text);
    return true;
}

bool LatticeEditor::release(QMouseEvent* e) {
    if (!drag_.active) {
        // A click (no drag) on empty space clears a point selection; the camera saw the press.
        if (e->button() == Qt::LeftButton && emptyPress_.x() >= 0) {
            const QPointF step = e->position() - emptyPress_;
            if (std::hypot(step.x(), step.y()) < kStartDistance && !(e->modifiers() & Qt::ControlModifier) &&
                selection_->kind() == Selection::Kind::LatticePoints)
                selection_->selectLattice(selection_->lattice());
        }
        emptyPress_ = QPointF(-1, -1);
        return false;
    }
    if (e->button() != Qt::LeftButton) return true;
    const Drag drag = drag_;
    drag_ = Drag{};
    viewport_->setCursor(pointAt(e->position()) ? Qt::OpenHandCursor : Qt::ArrowCursor);
    if (drag.cancelled || !drag.moved) return true;
    try {
        document_->moveLatticePoints(drag.lattice, drag.points, drag.delta);
        emit message(QString());
    } catch (const aero::Error& err) {
        document_->endPreview();
        emit message(tr("Cannot move: %1").arg(QString::fromStdString(err.what())));
    }
    viewport_->requestRender();
    return true;
}

void LatticeEditor::cancelDrag() {
    if (!drag_.active) return;
    drag_.cancelled = true;
    document_->endPreview();
    viewport_->setCursor(Qt::ArrowCursor);
    viewport_->requestRender();
    emit message(tr("Move cancelled"));
}

}  // namespace aero::ui
