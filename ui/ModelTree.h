#pragma once
// The model tree: Geometry (its patches), FFD volumes (the lattices) and Grid blocks (the
// parts of the mesh preview: control grid, wall, symmetry plane, slice), each with a visibility
// check box. Selecting items selects patches or a
// lattice (Selection); lattices with problems carry a warning icon and say why in a tooltip.
// GUI thread only; no VTK.
#include <QTreeWidget>

namespace aero::ui {

class Document;
class Selection;

class ModelTree : public QTreeWidget {
    Q_OBJECT

  public:
    enum ItemKind { GeometryItem = 1, PatchItem, LatticesItem, LatticeItem, GridItem, GridPartItem };
    /// The grid's parts, in the order of their items (and of MeshPart).
    enum GridPart { ControlGridPart = 0, WallPart, SymmetryPart, SlicePart, GridPartCount };
    static constexpr int KindRole = Qt::UserRole + 1;
    static constexpr int IndexRole = Qt::UserRole + 2;

    ModelTree(Document* document, Selection* selection, QWidget* parent = nullptr);

    QTreeWidgetItem* geometryItem() const { return geometry_; }
    QTreeWidgetItem* latticesItem() const { return lattices_; }
    QTreeWidgetItem* gridItem() const { return grid_; }
    QTreeWidgetItem* latticeItem(int lattice) const;
    QTreeWidgetItem* patchItem(int patch) const;
    QTreeWidgetItem* gridPartItem(int part) const;
    /// Whether grid part `part` is to be shown (its box and the Grid blocks box are checked).
    bool gridPartShown(int part) const;
    /// Describes the mesh preview on the Grid blocks item (`description`, e.g. "20 blocks", and
    /// a tooltip); the parts can be toggled while `available`.
    void setGridState(const QString& description, bool available, const QString& tooltip = {});

  signals:
    void geometryVisibilityChanged(bool visible);
    void patchVisibilityChanged(int patch, bool visible);
    void latticesVisibilityChanged(bool visible);
    void latticeVisibilityChanged(int lattice, bool visible);
    /// The Grid blocks box or one of its parts' boxes changed (see gridPartShown).
    void gridVisibilityChanged();

  private:
    void rebuild();
    void rebuildLattices();
    void updateDiagnostics();
    void onItemChanged(QTreeWidgetItem* item, int column);
    void onSelectionChanged();
    void showSelection();

    Document* document_;
    Selection* selection_;
    QTreeWidgetItem* geometry_ = nullptr;
    QTreeWidgetItem* lattices_ = nullptr;
    QTreeWidgetItem* grid_ = nullptr;
    bool updating_ = false;
};

}  // namespace aero::ui
