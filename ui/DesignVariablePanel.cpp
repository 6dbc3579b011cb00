#include "DesignVariablePanel.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QPainter>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyledItemDelegate>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "Document.h"

namespace aero::ui {

namespace {

const char* const kAxis = "XYZ";

QString describe(const ffd::DesignVariable& v) {
    const QChar axis = QLatin1Char(kAxis[std::clamp(v.axis, 0, 2)]);
    switch (v.kind) {
        case ffd::VariableKind::Translate:
            return QObject::tr("Translation of station %1 along %2").arg(v.station).arg(axis);
        case ffd::VariableKind::SectionScale:
            return QObject::tr("Section scaling along %1 of lattice point %2 (station %3)").arg(axis).arg(v.point).arg(v.station);
        case ffd::VariableKind::Taper:
            return QObject::tr("Taper (scaling along %1) of station %2").arg(axis).arg(v.station);
        case ffd::VariableKind::PointCoordinate:
            return QObject::tr("Coordinate %1 of lattice point %2").arg(axis).arg(v.point);
    }
    return {};
}

// Slider positions are steps of the bounds; values from the slider are rounded to 4 decimals
// so that the project file stays readable (0.36, not 0.36000000000000004).
double sliderValue(const ffd::DesignVariable& v, int position) {
    const double x = v.lower + (v.upper - v.lower) * position / DesignVariablePanel::kSliderSteps;
    return std::round(x * 1e4) / 1e4;
}
int sliderPosition(const ffd::DesignVariable& v, double value) {
    if (!(v.upper > v.lower)) return 0;
    return static_cast<int>(std::lround((value - v.lower) / (v.upper - v.lower) * DesignVariablePanel::kSliderSteps));
}

constexpr int kValueRole = Qt::UserRole;       // dJ/dv (double)
constexpr int kScaleRole = Qt::UserRole + 1;   // the largest |dJ/dv| (double)
constexpr int kCurrentRole = Qt::UserRole + 2; // false: the design changed since (grey)

// A signed bar from the cell's centre, to the right for dJ/dv > 0 and to the left for < 0, its
// length relative to the largest |dJ/dv|, with the value written over it.
class GradientBarDelegate : public QStyledItemDelegate {
  public:
    using QStyledItemDelegate::QStyledItemDelegate;

    void paint(QPainter* painter, const QStyleOptionViewItem& option, const QModelIndex& index) const override {
        const QVariant value = index.data(kValueRole);
        if (!value.isValid()) {
            QStyledItemDelegate::paint(painter, option, index);
            return;
        }
        const double v = value.toDouble(), scale = index.data(kScaleRole).toDouble();
        const bool current = index.data(kCurrentRole).toBool();
        painter->save();
        if (option.state & QStyle::State_Selected) painter->fillRect(option.rect, option.palette.highlight().color().lighter(170));
        const QRect r = option.rect.adjusted(3, 4, -3, -4);
        const int mid = r.center().x();
        const double t = scale > 0 && std::isfinite(v) ? std::clamp(v / scale, -1.0, 1.0) : 0.0;
        const int w = static_cast<int>(std::lround(t * (r.width() / 2)));
        QColor colour = v >= 0 ? QColor(46, 125, 196) : QColor(214, 96, 40);
        if (!current) colour = QColor(170, 170, 170);
        painter->fillRect(w >= 0 ? QRect(mid, r.top(), w, r.height()) : QRect(mid + w, r.top(), -w, r.height()), colour);
        painter->setPen(option.palette.mid().color());
        painter->drawLine(mid, option.rect.top() + 2, mid, option.rect.bottom() - 2);
        painter->setPen(current ? option.palette.text().color() : option.palette.placeholderText().color());
        // The value on the side the bar leaves free.
        painter->drawText(r.adjusted(2, 0, -2, 0), (v >= 0 ? Qt::AlignLeft : Qt::AlignRight) | Qt::AlignVCenter,
                          QLocale().toString(v, 'g', 2));
        painter->restore();
    }
};

}  // namespace

DesignVariablePanel::DesignVariablePanel(Document* document, QWidget* parent) : QWidget(parent), document_(document) {
    setObjectName(QStringLiteral("designVariablePanel"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(6, 6, 6, 6);
    auto* top = new QHBoxLayout;
    filter_ = new QLineEdit(this);
    filter_->setPlaceholderText(tr("Filter (e.g. S3 or taper)"));
    filter_->setClearButtonEnabled(true);
    top->addWidget(filter_, 1);
    reset_ = new QPushButton(tr("Reset All"), this);
    reset_->setToolTip(tr("All design variables back to their baseline values (undoable)"));
    top->addWidget(reset_);
    layout->addLayout(top);

    table_ = new QTableWidget(0, 4, this);
    table_->setObjectName(QStringLiteral("designVariableTable"));
    table_->setHorizontalHeaderLabels({tr("Variable"), tr("Range"), tr("Value"), tr("dJ/dv")});
    table_->verticalHeader()->hide();
    table_->verticalHeader()->setDefaultSectionSize(26);
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    table_->setSelectionMode(QAbstractItemView::SingleSelection);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->horizontalHeader()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
    table_->horizontalHeader()->setSectionResizeMode(1, QHeaderView::Stretch);
    table_->horizontalHeader()->setSectionResizeMode(2, QHeaderView::ResizeToContents);
    table_->horizontalHeaderItem(1)->setToolTip(tr("Drag within the variable's bounds"));
    table_->horizontalHeader()->setSectionResizeMode(kGradientColumn, QHeaderView::Fixed);
    table_->horizontalHeader()->resizeSection(kGradientColumn, 84);
    table_->horizontalHeaderItem(kGradientColumn)
        ->setToolTip(tr("The objective's derivative per unit change of each variable, from the adjoint gradient (Flow "
                        "\u25b8 Compute Sensitivities): blue bars increase J, orange ones decrease it. Click to sort: "
                        "largest first, smallest first, the variables' order."));
    table_->setItemDelegateForColumn(kGradientColumn, new GradientBarDelegate(table_));
    connect(table_->horizontalHeader(), &QHeaderView::sectionClicked, this, [this](int column) {
        if (column == kGradientColumn && !gradient_.empty()) sortByGradient((sortMode_ + 1) % 3);
    });
    layout->addWidget(table_, 1);

    empty_ = new QLabel(tr("No design variables. Add a lattice with station variables (FFD \u25b8 Add Lattice), or "
                           "drag lattice points directly."),
                        this);
    empty_->setWordWrap(true);
    empty_->setStyleSheet(QStringLiteral("color: palette(mid);"));
    layout->addWidget(empty_);

    sensitivity_ = new QCheckBox(tr("Show sensitivity dS/dv of the selected variable"), this);
    sensitivity_->setObjectName(QStringLiteral("showSensitivity"));
    sensitivity_->setToolTip(tr("Red arrows at surface points: how the surface moves per unit change of the "
                                "variable (the paper's Figure 1)"));
    layout->addWidget(sensitivity_);
    note_ = new QLabel(this);
    note_->setWordWrap(true);
    note_->hide();
    layout->addWidget(note_);

    // The objective's gradient and the prediction of the current edit.
    auto* gradientRow = new QHBoxLayout;
    gradientNote_ = new QLabel(this);
    gradientNote_->setObjectName(QStringLiteral("gradientNote"));
    gradientNote_->setWordWrap(true);
    gradientRow->addWidget(gradientNote_, 1);
    auto* computeColumn = new QVBoxLayout;
    objective_ = new QComboBox(this);
    objective_->setObjectName(QStringLiteral("gradientObjective"));
    objective_->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    objective_->setToolTip(tr("The objective J to differentiate: the case's optimization objective when it has one, "
                              "or a force coefficient"));
    computeColumn->addWidget(objective_);
    compute_ = new QPushButton(tr("Compute dJ/dv"), this);
    compute_->setObjectName(QStringLiteral("computeGradient"));
    compute_->setToolTip(tr("Solve the flow of the design as shown and its adjoint: dJ/dv of the objective for every "
                            "variable, dJ/dB at the lattice points (Flow \u25b8 Compute Sensitivities)"));
    computeColumn->addWidget(compute_);
    computeColumn->addStretch(1);
    gradientRow->addLayout(computeColumn);
    layout->addLayout(gradientRow);
    auto* predictionRow = new QHBoxLayout;
    prediction_ = new QLabel(this);
    prediction_->setObjectName(QStringLiteral("predictionLabel"));
    prediction_->setWordWrap(true);
    prediction_->setToolTip(tr("The first-order change of the objective from the design the gradient was computed at "
                               "to the design as shown (a drag included): the sum of dJ/dB . \u0394B over the lattice "
                               "points"));
    predictionRow->addWidget(prediction_, 1);
    confirm_ = new QPushButton(tr("Confirm with a Flow Solve"), this);
    confirm_->setObjectName(QStringLiteral("confirmPrediction"));
    confirm_->setToolTip(tr("Solve the flow of the design as shown and compare the actual change of the objective "
                            "with the prediction"));
    predictionRow->addWidget(confirm_, 0, Qt::AlignTop);
    layout->addLayout(predictionRow);
    clearGradient();
    setPrediction({}, false);
    connect(compute_, &QPushButton::clicked, this, &DesignVariablePanel::computeGradientRequested);
    connect(confirm_, &QPushButton::clicked, this, &DesignVariablePanel::confirmRequested);
    connect(objective_, &QComboBox::activated, this, &DesignVariablePanel::objectiveChosen);

    connect(filter_, &QLineEdit::textChanged, this, &DesignVariablePanel::applyFilter);
    connect(reset_, &QPushButton::clicked, document_, &Document::resetDesignValues);
    connect(sensitivity_, &QCheckBox::toggled, this, &DesignVariablePanel::sensitivityToggled);
    connect(table_, &QTableWidget::currentCellChanged, this, [this](int row, int, int previous, int) {
        if (row != previous && !updating_) emit currentVariableChanged(row);
    });
    connect(document_, &Document::reset, this, &DesignVariablePanel::rebuild);
    connect(document_, &Document::structureChanged, this, &DesignVariablePanel::rebuild);
    connect(document_, &Document::valuesChanged, this, &DesignVariablePanel::updateValues);
    rebuild();
}

int DesignVariablePanel::currentVariable() const {
    const int row = table_->currentRow();
    return row >= 0 && row < static_cast<int>(sliders_.size()) ? row : -1;
}

void DesignVariablePanel::setCurrentVariable(int var) {
    if (var < 0 || var >= table_->rowCount()) return;
    table_->setCurrentCell(var, 0);
    table_->scrollToItem(table_->item(var, 0), QAbstractItemView::PositionAtCenter);
}

bool DesignVariablePanel::sensitivityShown() const {
    return sensitivity_->isChecked();
}

void DesignVariablePanel::setSensitivityShown(bool on) {
    sensitivity_->setChecked(on);
}

void DesignVariablePanel::setSensitivityNote(const QString& text) {
    note_->setText(text);
    note_->setVisible(!text.isEmpty());
}

QSlider* DesignVariablePanel::slider(int var) const {
    return var >= 0 && var < static_cast<int>(sliders_.size()) ? sliders_[static_cast<std::size_t>(var)] : nullptr;
}

QDoubleSpinBox* DesignVariablePanel::spinBox(int var) const {
    return var >= 0 && var < static_cast<int>(spins_.size()) ? spins_[static_cast<std::size_t>(var)] : nullptr;
}

void DesignVariablePanel::rebuild() {
    updating_ = true;
    const int current = table_->currentRow();
    table_->clearContents();
    sliders_.clear();
    spins_.clear();
    const ffd::FfdModel* model = document_->model();
    const int n = model ? model->design().size() : 0;
    table_->setRowCount(n);
    for (int i = 0; i < n; ++i) {
        const ffd::DesignVariable& v = model->design().variables()[static_cast<std::size_t>(i)];
        auto* name = new QTableWidgetItem(QString::fromStdString(v.name));
        name->setToolTip(tr("%1\nbounds [%2, %3], baseline %4")
                             .arg(describe(v))
                             .arg(v.lower, 0, 'g', 6)
                             .arg(v.upper, 0, 'g', 6)
                             .arg(v.baseline, 0, 'g', 6));
        table_->setItem(i, 0, name);

        auto* slider = new QSlider(Qt::Horizontal);
        slider->setRange(0, kSliderSteps);
        slider->setPageStep(kSliderSteps / 20);
        slider->setFocusPolicy(Qt::StrongFocus);
        slider->setToolTip(tr("[%1, %2]").arg(v.lower, 0, 'g', 6).arg(v.upper, 0, 'g', 6));
        slider->installEventFilter(this);
        table_->setCellWidget(i, 1, slider);
        connect(slider, &QSlider::sliderPressed, this, [this] { gesture_ = nextGesture_++; });
        connect(slider, &QSlider::sliderReleased, this, [this] { gesture_ = 0; });
        connect(slider, &QSlider::valueChanged, this, [this, i](int pos) { sliderMoved(i, pos); });

        auto* spin = new QDoubleSpinBox;
        spin->setRange(v.lower, v.upper);
        spin->setDecimals(4);
        spin->setSingleStep((v.upper - v.lower) / 100.0);
        spin->setKeyboardTracking(false);
        spin->setFocusPolicy(Qt::StrongFocus);
        spin->setFrame(false);
        spin->installEventFilter(this);
        table_->setCellWidget(i, 2, spin);
        connect(spin, &QDoubleSpinBox::valueChanged, this, [this, i](double value) {
            if (!updating_) document_->setDesignValue(i, value);
        });
        sliders_.push_back(slider);
        spins_.push_back(spin);
        table_->setItem(i, kGradientColumn, new QTableWidgetItem);
    }
    if (static_cast<int>(gradient_.size()) != n) gradient_.clear();
    sortMode_ = 0;
    for (int i = 0; i < n; ++i) table_->verticalHeader()->moveSection(table_->verticalHeader()->visualIndex(i), i);
    fillGradientColumn();
    table_->setVisible(n > 0);
    filter_->setVisible(n > 0);
    compute_->setVisible(n > 0);
    objective_->setVisible(n > 0);
    reset_->setVisible(n > 0);
    sensitivity_->setVisible(n > 0);
    empty_->setVisible(n == 0);
    if (n == 0) note_->hide();
    updating_ = false;
    updateValues();
    applyFilter();
    if (n > 0) {
        updating_ = true;
        table_->setCurrentCell(std::clamp(current, 0, n - 1), 0);
        updating_ = false;
    }
    emit currentVariableChanged(currentVariable());
}

void DesignVariablePanel::updateValues() {
    const ffd::FfdModel* model = document_->model();
    const auto& values = document_->values();
    if (!model || static_cast<int>(values.size()) != static_cast<int>(sliders_.size())) return;
    updating_ = true;
    for (std::size_t i = 0; i < sliders_.size(); ++i) {
        const ffd::DesignVariable& v = model->design().variables()[i];
        const QSignalBlocker b1(sliders_[i]), b2(spins_[i]);
        if (!sliders_[i]->isSliderDown()) sliders_[i]->setValue(sliderPosition(v, values[i]));
        spins_[i]->setValue(values[i]);
        if (QTableWidgetItem* item = table_->item(static_cast<int>(i), 0)) {
            QFont f = item->font();
            f.setBold(values[i] != v.baseline);
            item->setFont(f);
        }
    }
    updating_ = false;
}

void DesignVariablePanel::applyFilter() {
    const QString text = filter_->text().trimmed();
    const ffd::FfdModel* model = document_->model();
    for (int i = 0; i < table_->rowCount(); ++i) {
        bool show = text.isEmpty();
        if (!show) {
            const QTableWidgetItem* item = table_->item(i, 0);
            show = item && (item->text().contains(text, Qt::CaseInsensitive) ||
                            (model && describe(model->design().variables()[static_cast<std::size_t>(i)]).contains(text, Qt::CaseInsensitive)));
        }
        table_->setRowHidden(i, !show);
    }
}

void DesignVariablePanel::sliderMoved(int var, int position) {
    if (updating_) return;
    const ffd::FfdModel* model = document_->model();
    if (!model || var >= model->design().size()) return;
    const ffd::DesignVariable& v = model->design().variables()[static_cast<std::size_t>(var)];
    table_->setCurrentCell(var, 0);
    document_->setDesignValue(var, sliderValue(v, position), gesture_);
}

bool DesignVariablePanel::eventFilter(QObject* watched, QEvent* event) {
    // The wheel scrolls the list; it changes a slider or spin box only once that has focus.
    if (event->type() == QEvent::Wheel) {
        auto* w = qobject_cast<QWidget*>(watched);
        if (w && !w->hasFocus()) {
            QApplication::sendEvent(table_->viewport(), event);
            return true;
        }
    }
    if (event->type() == QEvent::FocusIn) {
        // Focusing a row's editor makes it the current variable.
        for (std::size_t i = 0; i < sliders_.size(); ++i)
            if (watched == sliders_[i] || watched == spins_[i]) table_->setCurrentCell(static_cast<int>(i), 0);
    }
    return QWidget::eventFilter(watched, event);
}

// ---- The objective's gradient -------------------------------------------------------------------

void DesignVariablePanel::setGradient(const std::vector<double>& dJdv, const QString& objective, bool current,
                                      const QString& note) {
    gradient_ = dJdv;
    gradientCurrent_ = current;
    table_->horizontalHeaderItem(kGradientColumn)->setText(tr("d%1/dv").arg(objective));
    table_->setColumnHidden(kGradientColumn, false);
    fillGradientColumn();
    gradientNote_->setText(note);
    gradientNote_->setStyleSheet(current ? QString() : QStringLiteral("color: palette(mid);"));
    if (sortMode_ != 0) sortByGradient(sortMode_);
}

void DesignVariablePanel::clearGradient(const QString& note) {
    gradient_.clear();
    gradientCurrent_ = false;
    table_->horizontalHeaderItem(kGradientColumn)->setText(tr("dJ/dv"));
    table_->setColumnHidden(kGradientColumn, true);  // room for the sliders until there is a gradient
    fillGradientColumn();
    gradientNote_->setText(note.isEmpty() ? tr("No gradient yet: Compute dJ/dv shows which way each variable improves "
                                               "the objective.")
                                          : note);
    gradientNote_->setStyleSheet(QStringLiteral("color: palette(mid);"));
    sortByGradient(0);
}

double DesignVariablePanel::gradient(int var) const {
    return var >= 0 && var < static_cast<int>(gradient_.size()) ? gradient_[static_cast<std::size_t>(var)]
                                                                : std::numeric_limits<double>::quiet_NaN();
}

void DesignVariablePanel::fillGradientColumn() {
    double largest = 0;
    for (double g : gradient_)
        if (std::isfinite(g)) largest = std::max(largest, std::abs(g));
    for (int i = 0; i < table_->rowCount(); ++i) {
        QTableWidgetItem* item = table_->item(i, kGradientColumn);
        if (!item) continue;
        if (i < static_cast<int>(gradient_.size())) {
            const double g = gradient_[static_cast<std::size_t>(i)];
            item->setData(kValueRole, g);
            item->setData(kScaleRole, largest);
            item->setData(kCurrentRole, gradientCurrent_);
            item->setToolTip(tr("dJ/dv = %1%2").arg(g, 0, 'g', 6).arg(gradientCurrent_ ? QString() : tr(" (at an earlier design)")));
        } else {
            item->setData(kValueRole, QVariant());
            item->setToolTip({});
        }
    }
    table_->viewport()->update();
}

void DesignVariablePanel::sortByGradient(int mode) {
    sortMode_ = gradient_.empty() ? 0 : mode;
    const int n = table_->rowCount();
    std::vector<int> order(static_cast<std::size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    if (sortMode_ != 0 && static_cast<int>(gradient_.size()) == n) {
        std::stable_sort(order.begin(), order.end(), [this](int a, int b) {
            const double ga = gradient_[static_cast<std::size_t>(a)], gb = gradient_[static_cast<std::size_t>(b)];
            return sortMode_ == 1 ? ga > gb : ga < gb;
        });
    }
    // Visual order only (the vertical header's sections): rows stay the variables' indices.
    QHeaderView* rows = table_->verticalHeader();
    for (int to = 0; to < n; ++to) rows->moveSection(rows->visualIndex(order[static_cast<std::size_t>(to)]), to);
    table_->horizontalHeader()->setSortIndicatorShown(sortMode_ != 0);
    if (sortMode_ != 0)
        table_->horizontalHeader()->setSortIndicator(kGradientColumn, sortMode_ == 1 ? Qt::DescendingOrder : Qt::AscendingOrder);
}

std::vector<int> DesignVariablePanel::shownOrder() const {
    std::vector<int> order;
    for (int v = 0; v < table_->rowCount(); ++v) order.push_back(table_->verticalHeader()->logicalIndex(v));
    return order;
}

void DesignVariablePanel::setPrediction(const QString& text, bool canConfirm) {
    prediction_->setText(text);
    prediction_->setVisible(!text.isEmpty());
    confirm_->setVisible(!text.isEmpty());
    confirm_->setEnabled(canConfirm);
}

QString DesignVariablePanel::predictionText() const {
    return prediction_->text();
}

void DesignVariablePanel::setCanComputeGradient(bool on) {
    compute_->setEnabled(on);
    objective_->setEnabled(on);
}

void DesignVariablePanel::setObjectiveChoices(const QStringList& items, int current) {
    const QSignalBlocker block(objective_);
    objective_->clear();
    objective_->addItems(items);
    objective_->setCurrentIndex(current);
}

}  // namespace aero::ui
