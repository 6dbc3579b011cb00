#pragma once
// Picking and dragging lattice control points in the viewport.
//
// An event filter on the VtkViewport sees every mouse and key event before the viewport
// forwards it to VTK's camera style. Over a lattice point (screen-space nearest point within
// a few pixels, through the viewport's world-to-widget projection) it takes the event:
//   click            selects the point (Ctrl+click adds or removes it);
//   drag             moves the selected points in the plane through the grabbed point parallel
//                    to the view plane, the geometry following live (Document preview);
//   Shift+drag       moves them along the world axis (X, Y or Z) whose screen direction is
//                    closest to the drag;
//   release          commits one undoable edit; Escape during a drag cancels it.
// Elsewhere the events go on to the camera (rotate, pan, zoom); a click on empty space clears
// a point selection. Ctrl+A selects all points of the current lattice.
//
// GUI thread only. No VTK header: all projection goes through VtkViewport.
#include <QObject>
#include <QPointF>
#include <array>
#include <vector>

class QMouseEvent;

namespace aero::ui {

class Document;
class LatticeScene;
class Selection;
class VtkViewport;

class LatticeEditor : public QObject {
    Q_OBJECT

  public:
    LatticeEditor(VtkViewport* viewport, Document* document, Selection* selection, const LatticeScene* scene,
                  QObject* parent = nullptr);

    struct Hit {
        int lattice = -1;
        int point = -1;
        explicit operator bool() const { return lattice >= 0; }
    };
    /// The visible lattice point nearest to `pos` (widget coordinates) within pickRadius().
    Hit pointAt(const QPointF& pos) const;
    double pickRadius() const { return 9.0; }
    bool dragging() const { return drag_.active; }

  signals:
    /// What the editor is doing, for the status bar (empty: nothing to say).
    void message(const QString& text);

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    bool press(QMouseEvent* e);
    bool move(QMouseEvent* e);
    bool release(QMouseEvent* e);
    void cancelDrag();
    std::array<double, 3> dragDelta(const QPointF& pos, bool alongAxis);
    int chooseAxis(const QPointF& pos) const;

    VtkViewport* viewport_;
    Document* document_;
    Selection* selection_;
    const LatticeScene* scene_;

    struct Drag {
        bool active = false;      // a point was grabbed (mouse is down)
        bool moved = false;       // beyond the start threshold
        bool cancelled = false;   // Escape: ignore until release
        int lattice = -1;
        std::vector<int> points;
        QPointF pressPos;
        std::array<double, 3> grabbed{};  // world position of the grabbed point
        std::array<double, 3> normal{};   // drag plane normal (view direction at press)
        std::array<double, 3> start{};    // plane point under the cursor at press
        int axis = -1;                    // locked axis of a Shift drag
        std::array<double, 3> delta{};
    } drag_;
    QPointF emptyPress_{-1, -1};  // press on empty space (click detection)
};

}  // namespace aero::ui
