#include "PropertyPanel.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QStackedWidget>
#include <QVBoxLayout>
#include <cmath>

#include "Document.h"
#include "Selection.h"
#include "Text.h"
#include "common/Error.h"

namespace aero::ui {

namespace {

enum Page { HintPage, InfoPage, LatticePage, PointsPage };

QString number(double x) {
    return QString::number(x, 'g', 6);
}

QString patchList(const std::vector<int>& patches) {
    QStringList parts;
    for (std::size_t i = 0; i < patches.size() && i < 12; ++i) parts << QString::number(patches[i] + 1);
    if (patches.size() > 12) parts << QStringLiteral("\u2026");
    return parts.join(QStringLiteral(", "));
}

QLabel* wrapLabel(QWidget* parent) {
    auto* l = new QLabel(parent);
    l->setWordWrap(true);
    l->setTextFormat(Qt::RichText);
    l->setAlignment(Qt::AlignTop | Qt::AlignLeft);
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
    return l;
}

}  // namespace

PropertyPanel::PropertyPanel(Document* document, Selection* selection, QWidget* parent)
    : QWidget(parent), document_(document), selection_(selection) {
    setObjectName(QStringLiteral("propertyPanel"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(6, 6, 6, 6);
    pages_ = new QStackedWidget(this);
    layout->addWidget(pages_);

    // Hint.
    hint_ = wrapLabel(this);
    hint_->setText(tr("<p>Select an item in the model tree, or click a lattice point in the view.</p>"
                      "<p><b>Drag</b> a point to move it in the view plane, <b>Shift+drag</b> to move it along "
                      "X, Y or Z, <b>Ctrl+click</b> to select several; <b>Esc</b> cancels a drag.</p>"
                      "<p>Rotate with the left button, pan with the middle button (or Shift+left), zoom with the "
                      "wheel.</p>"));
    hint_->setStyleSheet(QStringLiteral("color: palette(mid);"));
    pages_->addWidget(hint_);

    // Geometry / patches.
    info_ = wrapLabel(this);
    pages_->addWidget(info_);

    // Lattice.
    auto* lattice = new QWidget(this);
    auto* lform = new QFormLayout(lattice);
    lform->setContentsMargins(0, 0, 0, 0);
    latticeName_ = new QLineEdit(lattice);
    latticeName_->setObjectName(QStringLiteral("latticeName"));
    lform->addRow(tr("Name"), latticeName_);
    auto triple = [&](auto& boxes, auto make, const QString& label, const QString& tip) {
        auto* row = new QWidget(lattice);
        auto* h = new QHBoxLayout(row);
        h->setContentsMargins(0, 0, 0, 0);
        h->setSpacing(4);
        for (int d = 0; d < 3; ++d) {
            boxes[static_cast<std::size_t>(d)] = make(row);
            boxes[static_cast<std::size_t>(d)]->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Fixed);
            boxes[static_cast<std::size_t>(d)]->setMinimumWidth(40);
            boxes[static_cast<std::size_t>(d)]->setToolTip(tip.arg(QLatin1Char("XYZ"[d])));
            h->addWidget(boxes[static_cast<std::size_t>(d)]);
        }
        lform->addRow(label, row);
    };
    triple(counts_, [](QWidget* p) {
        auto* s = new QSpinBox(p);
        s->setRange(2, 200);
        return s;
    }, tr("Points"), tr("Control points along lattice direction %1"));
    triple(degrees_, [](QWidget* p) {
        auto* s = new QSpinBox(p);
        s->setRange(1, 9);
        return s;
    }, tr("Degrees"), tr("Polynomial degree along lattice direction %1"));
    triple(padding_, [](QWidget* p) {
        auto* s = new QDoubleSpinBox(p);
        s->setRange(0.0, 10.0);
        s->setDecimals(3);
        s->setSingleStep(0.01);
        s->setButtonSymbols(QAbstractSpinBox::NoButtons);  // room for the digits in a narrow dock
        return s;
    }, tr("Padding"), tr("Margin around the geometry along %1, relative to its extent"));
    for (int d = 0; d < 3; ++d) {
        connect(degrees_[static_cast<std::size_t>(d)], &QSpinBox::valueChanged, this, [this, d](int degree) {
            counts_[static_cast<std::size_t>(d)]->setMinimum(degree + 1);
        });
    }
    latticeInfo_ = wrapLabel(lattice);
    lform->addRow(latticeInfo_);
    latticeError_ = wrapLabel(lattice);
    latticeError_->setStyleSheet(QStringLiteral("color: #b00020;"));
    latticeError_->hide();
    lform->addRow(latticeError_);
    auto* buttons = new QHBoxLayout;
    apply_ = new QPushButton(tr("Apply"), lattice);
    apply_->setObjectName(QStringLiteral("applyLattice"));
    apply_->setToolTip(tr("Rebuild the lattice with these settings (undoable)"));
    remove_ = new QPushButton(tr("Remove"), lattice);
    remove_->setToolTip(tr("Remove this lattice with its design variables and displacements (undoable)"));
    buttons->addStretch();
    buttons->addWidget(remove_);
    buttons->addWidget(apply_);
    lform->addRow(buttons);
    pages_->addWidget(lattice);
    connect(apply_, &QPushButton::clicked, this, &PropertyPanel::applyLattice);
    connect(latticeName_, &QLineEdit::returnPressed, this, &PropertyPanel::applyLattice);
    connect(remove_, &QPushButton::clicked, this, [this] {
        if (selection_->lattice() >= 0) document_->removeLattice(selection_->lattice());
    });

    // Lattice points.
    auto* points = new QWidget(this);
    auto* pform = new QFormLayout(points);
    pform->setContentsMargins(0, 0, 0, 0);
    pointsTitle_ = wrapLabel(points);
    pform->addRow(pointsTitle_);
    for (int d = 0; d < 3; ++d) {
        auto* box = new QDoubleSpinBox(points);
        box->setObjectName(QStringLiteral("coordinate%1").arg(QLatin1Char("xyz"[d])));
        box->setRange(-1e6, 1e6);
        box->setDecimals(6);
        box->setSingleStep(0.01);
        box->setKeyboardTracking(false);  // one edit per committed value, not per keystroke
        box->setAccelerated(true);
        box->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Fixed);  // fits a narrow dock
        box->setMinimumWidth(80);
        coords_[static_cast<std::size_t>(d)] = box;
        pform->addRow(QString(QLatin1Char("XYZ"[d])), box);
        connect(box, &QDoubleSpinBox::valueChanged, this, [this, d](double v) { coordinateEdited(d, v); });
    }
    pointsInfo_ = wrapLabel(points);
    pform->addRow(pointsInfo_);
    resetPoints_ = new QPushButton(tr("Reset to Lattice Position"), points);
    resetPoints_->setToolTip(tr("Remove the displacements of the selected points (undoable)"));
    pform->addRow(resetPoints_);
    connect(resetPoints_, &QPushButton::clicked, this, [this] {
        document_->resetLatticePoints(selection_->lattice(), selection_->points());
    });
    pages_->addWidget(points);

    connect(selection_, &Selection::changed, this, &PropertyPanel::refresh);
    connect(document_, &Document::reset, this, &PropertyPanel::refresh);
    connect(document_, &Document::structureChanged, this, &PropertyPanel::refresh);
    connect(document_, &Document::diagnosticsChanged, this, [this] {
        if (pages_->currentIndex() == LatticePage || pages_->currentIndex() == InfoPage) refresh();
    });
    connect(document_, &Document::latticesMoved, this, &PropertyPanel::refreshPoints);
    refresh();
}

void PropertyPanel::refresh() {
    latticeError_->hide();
    const geometry::PatchSet& set = document_->baseline();
    switch (selection_->kind()) {
        case Selection::Kind::None:
            pages_->setCurrentIndex(HintPage);
            return;
        case Selection::Kind::Geometry: {
            const auto box = geometry::controlBoundingBox(set);
            QString text = tr("<b>Geometry</b><br>%1<br>%2, %3")
                               .arg(document_->hasGeometry() ? QString::fromStdString(set.source).toHtmlEscaped() : QString(),
                                    counted(set.size(), tr("patch"), tr("patches")),
                                    counted(set.controlPointCount(), tr("control point"), tr("control points")));
            if (const ffd::FfdModel* m = document_->model())
                text += tr("<br>%1 unique, %2 embedded in lattices").arg(m->summary().unique).arg(m->summary().embedded);
            if (set.size() > 0)
                text += tr("<br>Bounds: x [%1, %2], y [%3, %4], z [%5, %6]")
                            .arg(number(box.min[0]), number(box.max[0]), number(box.min[1]), number(box.max[1]),
                                 number(box.min[2]), number(box.max[2]));
            const QStringList problems = document_->problems();
            if (!problems.isEmpty())
                text += QStringLiteral("<p style='color:#b00020'>%1</p>").arg(problems.join(QStringLiteral("<br>")).toHtmlEscaped());
            info_->setText(text);
            pages_->setCurrentIndex(InfoPage);
            return;
        }
        case Selection::Kind::Patches: {
            const auto& ps = selection_->patches();
            QString text;
            if (ps.size() == 1 && ps[0] < set.size()) {
                const int p = ps[0];
                const auto& s = set.patches[static_cast<std::size_t>(p)];
                const std::string& name = p < static_cast<int>(set.names.size()) ? set.names[static_cast<std::size_t>(p)] : std::string();
                text = tr("<b>Patch %1</b> %2<br>%3 \u00d7 %4 control points<br>degrees %5 \u00d7 %6%7<br>u in [%8, %9], v in [%10, %11]")
                           .arg(p + 1)
                           .arg(name.empty() ? QString() : QStringLiteral("'%1'").arg(QString::fromStdString(name).toHtmlEscaped()))
                           .arg(s.countU)
                           .arg(s.countV)
                           .arg(s.degreeU)
                           .arg(s.degreeV)
                           .arg(s.rational() ? tr(", rational") : tr(", polynomial"))
                           .arg(number(s.knotsU[static_cast<std::size_t>(s.degreeU)]), number(s.knotsU[static_cast<std::size_t>(s.countU)]),
                                number(s.knotsV[static_cast<std::size_t>(s.degreeV)]), number(s.knotsV[static_cast<std::size_t>(s.countV)]));
            } else {
                text = tr("<b>%1</b> selected: ").arg(counted(static_cast<long long>(ps.size()), tr("patch"), tr("patches"))) + patchList(ps);
            }
            text += tr("<p>FFD \u25b8 Add Lattice places a lattice around the selected patches.</p>");
            info_->setText(text);
            pages_->setCurrentIndex(InfoPage);
            return;
        }
        case Selection::Kind::Lattice: {
            const int l = selection_->lattice();
            const auto& lattices = document_->caseFile().lattices;
            if (l < 0 || l >= static_cast<int>(lattices.size())) {
                pages_->setCurrentIndex(HintPage);
                return;
            }
            const io::LatticeCase& lc = lattices[static_cast<std::size_t>(l)];
            updating_ = true;
            latticeName_->setText(QString::fromStdString(lc.name));
            for (int d = 0; d < 3; ++d) {
                const auto k = static_cast<std::size_t>(d);
                degrees_[k]->setValue(lc.degrees[k]);
                counts_[k]->setMinimum(lc.degrees[k] + 1);
                counts_[k]->setValue(lc.counts[k]);
                padding_[k]->setValue(lc.padding[k]);
                padding_[k]->setEnabled(!lc.box.has_value());
            }
            updating_ = false;
            QString text = lc.patches.empty() ? tr("Around all patches.") : tr("Around patches %1.").arg(patchList(lc.patches));
            if (lc.box) text += tr(" Explicit box (padding unused).");
            if (!lc.refine.empty() || !lc.crease.empty()) text += tr(" Refined/creased in the case file.");
            const auto& reports = document_->injectivity();
            if (l < static_cast<int>(reports.size())) {
                const auto& r = reports[static_cast<std::size_t>(l)];
                text += r.injective ? tr("<br>Injective (%1), min det J / mean = %2.")
                                          .arg(r.certified ? tr("certified") : tr("sampled"))
                                          .arg(number(r.relativeMinJacobian))
                                    : tr("<br><span style='color:#b00020'><b>Not injective</b>: det J changes sign near "
                                         "(%1, %2, %3).</span>")
                                          .arg(number(r.minPoint[0]), number(r.minPoint[1]), number(r.minPoint[2]));
            }
            int displaced = 0;
            for (const auto& d : document_->caseFile().displacements) displaced += d.lattice == l ? 1 : 0;
            if (displaced > 0) text += tr("<br>%1.").arg(counted(displaced, tr("displaced point"), tr("displaced points")));
            latticeInfo_->setText(text);
            pages_->setCurrentIndex(LatticePage);
            return;
        }
        case Selection::Kind::LatticePoints:
            pages_->setCurrentIndex(PointsPage);
            refreshPoints();
            return;
    }
}

void PropertyPanel::refreshPoints() {
    if (selection_->kind() != Selection::Kind::LatticePoints) return;
    const int l = selection_->lattice();
    const auto& lattices = document_->lattices();
    if (l < 0 || l >= static_cast<int>(lattices.size())) return;
    const ffd::Lattice& L = lattices[static_cast<std::size_t>(l)];
    const auto& pts = selection_->points();
    std::array<double, 3> centre{0, 0, 0};
    int n = 0;
    for (int a : pts) {
        if (a < 0 || a >= L.controlCount()) continue;
        for (int k = 0; k < 3; ++k) centre[static_cast<std::size_t>(k)] += L.points[3 * static_cast<std::size_t>(a) + k];
        ++n;
    }
    if (n == 0) return;
    for (double& c : centre) c /= n;
    const QString name = QString::fromStdString(document_->caseFile().lattices[static_cast<std::size_t>(l)].name).toHtmlEscaped();
    if (n == 1) {
        const int a = pts[0];
        const int i = a % L.count[0], j = (a / L.count[0]) % L.count[1], k = a / (L.count[0] * L.count[1]);
        pointsTitle_->setText(tr("<b>Lattice point (%1, %2, %3)</b> of '%4'").arg(i).arg(j).arg(k).arg(name));
        const auto d = document_->displacement(l, a);
        pointsInfo_->setText(d == std::array<double, 3>{0, 0, 0}
                                 ? tr("Not displaced.")
                                 : tr("Displaced by (%1, %2, %3).").arg(number(d[0]), number(d[1]), number(d[2])));
    } else {
        pointsTitle_->setText(tr("<b>%1</b> of '%2' \u2014 centroid:").arg(counted(n, tr("lattice point"), tr("lattice points")), name));
        pointsInfo_->setText(tr("Editing a coordinate moves all selected points by the same amount."));
    }
    updating_ = true;
    for (int k = 0; k < 3; ++k) {
        QDoubleSpinBox* box = coords_[static_cast<std::size_t>(k)];
        if (!box->hasFocus() || document_->previewing()) box->setValue(centre[static_cast<std::size_t>(k)]);
    }
    updating_ = false;
}

void PropertyPanel::coordinateEdited(int axis, double value) {
    if (updating_ || selection_->kind() != Selection::Kind::LatticePoints) return;
    const int l = selection_->lattice();
    const auto& lattices = document_->lattices();
    if (l < 0 || l >= static_cast<int>(lattices.size())) return;
    const ffd::Lattice& L = lattices[static_cast<std::size_t>(l)];
    const auto& pts = selection_->points();
    try {
        if (pts.size() == 1) {
            const double* x = &L.points[3 * static_cast<std::size_t>(pts[0])];
            std::array<double, 3> p{x[0], x[1], x[2]};
            p[static_cast<std::size_t>(axis)] = value;
            document_->setLatticePointPosition(l, pts[0], p);
        } else {
            double mean = 0;
            for (int a : pts) mean += L.points[3 * static_cast<std::size_t>(a) + static_cast<std::size_t>(axis)];
            mean /= static_cast<double>(pts.size());
            std::array<double, 3> delta{0, 0, 0};
            delta[static_cast<std::size_t>(axis)] = value - mean;
            if (std::abs(delta[static_cast<std::size_t>(axis)]) > 0) document_->moveLatticePoints(l, pts, delta);
        }
    } catch (const aero::Error& e) {
        pointsInfo_->setText(QStringLiteral("<span style='color:#b00020'>%1</span>").arg(QString::fromStdString(e.what()).toHtmlEscaped()));
    }
}

void PropertyPanel::applyLattice() {
    const int l = selection_->lattice();
    if (selection_->kind() != Selection::Kind::Lattice || l < 0 || l >= document_->latticeCount()) return;
    io::LatticeCase lc = document_->caseFile().lattices[static_cast<std::size_t>(l)];
    lc.name = latticeName_->text().trimmed().toStdString();
    for (int d = 0; d < 3; ++d) {
        const auto k = static_cast<std::size_t>(d);
        lc.counts[k] = counts_[k]->value();
        lc.degrees[k] = degrees_[k]->value();
        // Keep a padding the spin box cannot show exactly unless the user changed it.
        const double shown = std::round(lc.padding[k] * 1000.0) / 1000.0;
        if (padding_[k]->value() != shown) lc.padding[k] = padding_[k]->value();
    }
    const io::LatticeCase& old = document_->caseFile().lattices[static_cast<std::size_t>(l)];
    if (lc.name == old.name && lc.counts == old.counts && lc.degrees == old.degrees && lc.padding == old.padding) return;
    try {
        document_->editLattice(l, lc);
        latticeError_->hide();
    } catch (const aero::Error& e) {
        latticeError_->setText(QString::fromStdString(e.what()).toHtmlEscaped());
        latticeError_->show();
    }
}

}  // namespace aero::ui
