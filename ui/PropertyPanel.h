#pragma once
// Properties of the selection: the geometry, patches, a lattice (editable: name, counts,
// degrees, padding; Apply makes one undoable edit), or lattice points (exact coordinates that
// can be typed; the points move as if dragged). GUI thread only; no VTK.
#include <QWidget>
#include <array>

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QSpinBox;
class QStackedWidget;

namespace aero::ui {

class Document;
class Selection;

class PropertyPanel : public QWidget {
    Q_OBJECT

  public:
    PropertyPanel(Document* document, Selection* selection, QWidget* parent = nullptr);

    /// The coordinate editors of the point page (x, y, z), for tests and keyboard users.
    std::array<QDoubleSpinBox*, 3> coordinateEditors() const { return coords_; }

  private:
    void refresh();
    void refreshPoints();
    void applyLattice();
    void coordinateEdited(int axis, double value);

    Document* document_;
    Selection* selection_;
    QStackedWidget* pages_ = nullptr;
    QLabel* hint_ = nullptr;
    QLabel* info_ = nullptr;
    // Lattice page.
    QLineEdit* latticeName_ = nullptr;
    std::array<QSpinBox*, 3> counts_{};
    std::array<QSpinBox*, 3> degrees_{};
    std::array<QDoubleSpinBox*, 3> padding_{};
    QLabel* latticeInfo_ = nullptr;
    QLabel* latticeError_ = nullptr;
    QPushButton* apply_ = nullptr;
    QPushButton* remove_ = nullptr;
    // Points page.
    QLabel* pointsTitle_ = nullptr;
    std::array<QDoubleSpinBox*, 3> coords_{};
    QLabel* pointsInfo_ = nullptr;
    QPushButton* resetPoints_ = nullptr;
    bool updating_ = false;
};

}  // namespace aero::ui
