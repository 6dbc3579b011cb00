#include "ModelTree.h"

#include <QApplication>
#include <QHeaderView>
#include <QStyle>

#include "Document.h"
#include "Selection.h"
#include "Text.h"

namespace aero::ui {

namespace {

QTreeWidgetItem* makeItem(QTreeWidgetItem* parent, const QString& text, int kind, int index, bool checkable) {
    auto* item = new QTreeWidgetItem(parent, QStringList{text});
    item->setData(0, ModelTree::KindRole, kind);
    item->setData(0, ModelTree::IndexRole, index);
    if (checkable) {
        item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
        item->setCheckState(0, Qt::Checked);
    }
    return item;
}

int kindOf(const QTreeWidgetItem* item) {
    return item ? item->data(0, ModelTree::KindRole).toInt() : 0;
}
int indexOf(const QTreeWidgetItem* item) {
    return item ? item->data(0, ModelTree::IndexRole).toInt() : -1;
}

}  // namespace

ModelTree::ModelTree(Document* document, Selection* selection, QWidget* parent)
    : QTreeWidget(parent), document_(document), selection_(selection) {
    setObjectName(QStringLiteral("modelTree"));
    setHeaderHidden(true);
    setColumnCount(1);
    setSelectionMode(QAbstractItemView::ExtendedSelection);
    setUniformRowHeights(true);
    header()->setStretchLastSection(true);

    updating_ = true;
    geometry_ = makeItem(nullptr, tr("Geometry"), GeometryItem, -1, true);
    lattices_ = makeItem(nullptr, tr("FFD volumes"), LatticesItem, -1, true);
    grid_ = makeItem(nullptr, tr("Grid blocks"), GridItem, -1, true);
    addTopLevelItems({geometry_, lattices_, grid_});
    const QString parts[GridPartCount] = {tr("Control grid"), tr("Wall"), tr("Symmetry plane"), tr("Slice (k = const)")};
    const QString tips[GridPartCount] = {
        tr("The control grid b of the B-spline volume blocks (wireframe)"),
        tr("The grid's faces on the body, coloured by the cell quality"),
        tr("The grid's faces on the symmetry plane Y = 0, coloured by the cell quality"),
        tr("One layer of cells k = const around the body (choose it in the Mesh Quality panel)")};
    for (int p = 0; p < GridPartCount; ++p) {
        auto* item = makeItem(grid_, parts[p], GridPartItem, p, true);
        item->setToolTip(0, tips[p]);
        if (p == ControlGridPart || p == SlicePart) item->setCheckState(0, Qt::Unchecked);
    }
    updating_ = false;
    setGridState({}, false);

    connect(this, &QTreeWidget::itemChanged, this, &ModelTree::onItemChanged);
    connect(this, &QTreeWidget::itemSelectionChanged, this, &ModelTree::onSelectionChanged);
    connect(document_, &Document::reset, this, &ModelTree::rebuild);
    connect(document_, &Document::structureChanged, this, &ModelTree::rebuildLattices);
    connect(document_, &Document::diagnosticsChanged, this, &ModelTree::updateDiagnostics);
    connect(selection_, &Selection::changed, this, &ModelTree::showSelection);
    rebuild();
}

QTreeWidgetItem* ModelTree::latticeItem(int lattice) const {
    return lattice >= 0 && lattice < lattices_->childCount() ? lattices_->child(lattice) : nullptr;
}

QTreeWidgetItem* ModelTree::patchItem(int patch) const {
    return patch >= 0 && patch < geometry_->childCount() ? geometry_->child(patch) : nullptr;
}

QTreeWidgetItem* ModelTree::gridPartItem(int part) const {
    return part >= 0 && part < grid_->childCount() ? grid_->child(part) : nullptr;
}

bool ModelTree::gridPartShown(int part) const {
    const QTreeWidgetItem* item = gridPartItem(part);
    return item && item->checkState(0) == Qt::Checked && grid_->checkState(0) == Qt::Checked;
}

void ModelTree::setGridState(const QString& description, bool available, const QString& tooltip) {
    updating_ = true;
    grid_->setText(0, description.isEmpty() ? tr("Grid blocks") : tr("Grid blocks \u2014 %1").arg(description));
    grid_->setToolTip(0, !tooltip.isEmpty() ? tooltip
                         : available        ? tr("The mesh preview's structured grid blocks")
                                            : tr("Run Mesh > Preview (Ctrl+M) to generate the grid blocks"));
    for (int p = 0; p < grid_->childCount(); ++p) {
        QTreeWidgetItem* item = grid_->child(p);
        item->setDisabled(!available);
    }
    grid_->setExpanded(available);
    updating_ = false;
}

void ModelTree::rebuild() {
    updating_ = true;
    qDeleteAll(geometry_->takeChildren());
    const geometry::PatchSet& set = document_->baseline();
    geometry_->setText(0, document_->hasGeometry() ? tr("Geometry \u2014 %1").arg(counted(set.size(), tr("patch"), tr("patches"))) : tr("Geometry"));
    geometry_->setCheckState(0, Qt::Checked);
    for (int p = 0; p < set.size(); ++p) {
        const std::string& name = p < static_cast<int>(set.names.size()) ? set.names[static_cast<std::size_t>(p)] : std::string();
        const QString text = name.empty() ? tr("Patch %1").arg(p + 1) : tr("Patch %1 '%2'").arg(p + 1).arg(QString::fromStdString(name));
        auto* item = makeItem(geometry_, text, PatchItem, p, true);
        const auto& s = set.patches[static_cast<std::size_t>(p)];
        item->setToolTip(0, tr("%1 x %2 control points, degrees %3 x %4%5")
                                .arg(s.countU)
                                .arg(s.countV)
                                .arg(s.degreeU)
                                .arg(s.degreeV)
                                .arg(s.rational() ? tr(", rational") : QString()));
    }
    geometry_->setExpanded(false);
    lattices_->setCheckState(0, Qt::Checked);
    qDeleteAll(lattices_->takeChildren());
    updating_ = false;
    rebuildLattices();
}

void ModelTree::rebuildLattices() {
    updating_ = true;
    std::vector<Qt::CheckState> states;
    for (int i = 0; i < lattices_->childCount(); ++i) states.push_back(lattices_->child(i)->checkState(0));
    qDeleteAll(lattices_->takeChildren());
    const auto& lattices = document_->caseFile().lattices;
    const bool keep = states.size() == lattices.size();
    for (int l = 0; l < static_cast<int>(lattices.size()); ++l) {
        const auto& lc = lattices[static_cast<std::size_t>(l)];
        const QString text = tr("%1 \u2014 %2\u00d7%3\u00d7%4")
                                 .arg(QString::fromStdString(lc.name))
                                 .arg(lc.counts[0])
                                 .arg(lc.counts[1])
                                 .arg(lc.counts[2]);
        auto* item = makeItem(lattices_, text, LatticeItem, l, true);
        if (keep) item->setCheckState(0, states[static_cast<std::size_t>(l)]);
    }
    lattices_->setExpanded(true);
    updating_ = false;
    updateDiagnostics();
    showSelection();
}

void ModelTree::updateDiagnostics() {
    const auto& reports = document_->injectivity();
    const QIcon warning = QApplication::style()->standardIcon(QStyle::SP_MessageBoxWarning);
    updating_ = true;
    for (int l = 0; l < lattices_->childCount(); ++l) {
        QTreeWidgetItem* item = lattices_->child(l);
        const bool bad = l < static_cast<int>(reports.size()) && !reports[static_cast<std::size_t>(l)].injective;
        item->setIcon(0, bad ? warning : QIcon());
        item->setToolTip(0, bad ? tr("Not injective: the lattice folds (det J changes sign); the geometry inside "
                                     "can self-intersect.")
                                : tr("Injective lattice (det J keeps its sign)."));
    }
    const QStringList problems = document_->problems();
    bool outside = false;
    for (const QString& p : problems) outside = outside || p.contains(QLatin1String("outside"));
    geometry_->setIcon(0, outside ? warning : QIcon());
    geometry_->setToolTip(0, outside ? problems.join(QLatin1Char('\n')) : QString());
    updating_ = false;
}

void ModelTree::onItemChanged(QTreeWidgetItem* item, int column) {
    if (updating_ || column != 0 || !(item->flags() & Qt::ItemIsUserCheckable)) return;
    const bool on = item->checkState(0) == Qt::Checked;
    switch (kindOf(item)) {
        case GeometryItem:
            emit geometryVisibilityChanged(on);
            break;
        case PatchItem:
            emit patchVisibilityChanged(indexOf(item), on);
            break;
        case LatticesItem:
            emit latticesVisibilityChanged(on);
            break;
        case LatticeItem:
            emit latticeVisibilityChanged(indexOf(item), on);
            break;
        case GridItem:
        case GridPartItem:
            emit gridVisibilityChanged();
            break;
        default:
            break;
    }
}

void ModelTree::onSelectionChanged() {
    if (updating_) return;
    const QList<QTreeWidgetItem*> items = selectedItems();
    std::vector<int> patches;
    int lattice = -1;
    bool geometry = false;
    for (QTreeWidgetItem* item : items) {
        switch (kindOf(item)) {
            case PatchItem:
                patches.push_back(indexOf(item));
                break;
            case LatticeItem:
                lattice = indexOf(item);
                break;
            case GeometryItem:
                geometry = true;
                break;
            default:
                break;
        }
    }
    updating_ = true;
    if (!patches.empty())
        selection_->selectPatches(patches);
    else if (lattice >= 0) {
        // Keep a point selection of the same lattice (the tree shows its lattice).
        if (!(selection_->kind() == Selection::Kind::LatticePoints && selection_->lattice() == lattice))
            selection_->selectLattice(lattice);
    } else if (geometry)
        selection_->selectGeometry();
    else
        selection_->clear();
    updating_ = false;
}

void ModelTree::showSelection() {
    if (updating_) return;
    updating_ = true;
    clearSelection();
    switch (selection_->kind()) {
        case Selection::Kind::Geometry:
            geometry_->setSelected(true);
            break;
        case Selection::Kind::Patches:
            for (int p : selection_->patches())
                if (QTreeWidgetItem* item = patchItem(p)) {
                    item->setSelected(true);
                    geometry_->setExpanded(true);
                }
            break;
        case Selection::Kind::Lattice:
        case Selection::Kind::LatticePoints:
            if (QTreeWidgetItem* item = latticeItem(selection_->lattice())) {
                item->setSelected(true);
                scrollToItem(item);
            }
            break;
        default:
            break;
    }
    updating_ = false;
}

}  // namespace aero::ui
