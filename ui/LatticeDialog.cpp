#include "LatticeDialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QRadioButton>
#include <QSpinBox>
#include <QVBoxLayout>

#include "Text.h"

namespace aero::ui {

LatticeDialog::LatticeDialog(const QString& suggestedName, const std::vector<int>& selectedPatches, QWidget* parent)
    : QDialog(parent), selection_(selectedPatches) {
    setWindowTitle(tr("Add FFD Lattice"));
    setObjectName(QStringLiteral("latticeDialog"));
    auto* layout = new QVBoxLayout(this);

    auto* form = new QFormLayout;
    name_ = new QLineEdit(suggestedName, this);
    form->addRow(tr("Name"), name_);
    const io::LatticeCase defaults;  // the paper's 6x6x2, cubic/cubic/linear
    auto triple = [&](auto& boxes, auto make, const QString& label) {
        auto* row = new QWidget(this);
        auto* h = new QHBoxLayout(row);
        h->setContentsMargins(0, 0, 0, 0);
        for (int d = 0; d < 3; ++d) {
            auto* axis = new QLabel(QString(QLatin1Char("XYZ"[d])), row);
            h->addWidget(axis);
            boxes[static_cast<std::size_t>(d)] = make(row, d);
            h->addWidget(boxes[static_cast<std::size_t>(d)], 1);
        }
        form->addRow(label, row);
    };
    triple(counts_, [&](QWidget* p, int d) {
        auto* s = new QSpinBox(p);
        s->setRange(2, 200);
        s->setValue(defaults.counts[static_cast<std::size_t>(d)]);
        return s;
    }, tr("Control points"));
    triple(degrees_, [&](QWidget* p, int d) {
        auto* s = new QSpinBox(p);
        s->setRange(1, 9);
        s->setValue(defaults.degrees[static_cast<std::size_t>(d)]);
        return s;
    }, tr("Degrees"));
    triple(padding_, [&](QWidget* p, int d) {
        auto* s = new QDoubleSpinBox(p);
        s->setRange(0.0, 10.0);
        s->setDecimals(3);
        s->setSingleStep(0.01);
        s->setValue(defaults.padding[static_cast<std::size_t>(d)]);
        s->setToolTip(tr("Margin relative to the geometry's extent (0: a face touches the extreme control points, "
                         "e.g. on a symmetry plane)"));
        return s;
    }, tr("Padding"));
    for (int d = 0; d < 3; ++d) {
        const auto k = static_cast<std::size_t>(d);
        counts_[k]->setMinimum(degrees_[k]->value() + 1);
        connect(degrees_[k], &QSpinBox::valueChanged, counts_[k], [this, k](int degree) { counts_[k]->setMinimum(degree + 1); });
    }
    layout->addLayout(form);

    auto* scope = new QGroupBox(tr("Around"), this);
    auto* sv = new QVBoxLayout(scope);
    allPatches_ = new QRadioButton(tr("All patches"), scope);
    selectedPatches_ = new QRadioButton(tr("The %1 selected").arg(counted(static_cast<long long>(selection_.size()), tr("patch"), tr("patches"))), scope);
    selectedPatches_->setEnabled(!selection_.empty());
    (selection_.empty() ? allPatches_ : selectedPatches_)->setChecked(true);
    if (selection_.empty()) selectedPatches_->setToolTip(tr("Select patches in the model tree first"));
    sv->addWidget(allPatches_);
    sv->addWidget(selectedPatches_);
    layout->addWidget(scope);

    stationsBox_ = new QGroupBox(tr("Station design variables (as in the paper)"), this);
    stationsBox_->setCheckable(true);
    stationsBox_->setChecked(false);
    stationsBox_->setToolTip(tr("Slices of the lattice that translate, scale their sections and taper"));
    auto* st = new QFormLayout(stationsBox_);
    direction_ = new QComboBox(stationsBox_);
    direction_->addItems({tr("X"), tr("Y (spanwise)"), tr("Z")});
    direction_->setCurrentIndex(1);
    st->addRow(tr("Stations along"), direction_);
    auto* tr3 = new QWidget(stationsBox_);
    auto* th = new QHBoxLayout(tr3);
    th->setContentsMargins(0, 0, 0, 0);
    for (int d = 0; d < 3; ++d) {
        translate_[static_cast<std::size_t>(d)] = new QCheckBox(QString(QLatin1Char("XYZ"[d])), tr3);
        th->addWidget(translate_[static_cast<std::size_t>(d)]);
    }
    translate_[0]->setChecked(true);
    translate_[1]->setChecked(true);
    th->addStretch();
    st->addRow(tr("Translations"), tr3);
    bound_ = new QDoubleSpinBox(stationsBox_);
    bound_->setRange(0.001, 1000.0);
    bound_->setDecimals(3);
    bound_->setValue(1.0);
    st->addRow(tr("Translation bound"), bound_);
    scaling_ = new QCheckBox(tr("Section scaling (vertical, per point)"), stationsBox_);
    scaling_->setChecked(true);
    st->addRow(scaling_);
    taper_ = new QCheckBox(tr("Taper (streamwise, per station)"), stationsBox_);
    taper_->setChecked(true);
    st->addRow(taper_);
    layout->addWidget(stationsBox_);

    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
    buttons->button(QDialogButtonBox::Ok)->setText(tr("Add Lattice"));
    connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    connect(name_, &QLineEdit::textChanged, this, [buttons](const QString& t) {
        buttons->button(QDialogButtonBox::Ok)->setEnabled(!t.trimmed().isEmpty());
    });
    layout->addWidget(buttons);
}

io::LatticeCase LatticeDialog::lattice() const {
    io::LatticeCase l;
    l.name = name_->text().trimmed().toStdString();
    for (int d = 0; d < 3; ++d) {
        const auto k = static_cast<std::size_t>(d);
        l.counts[k] = counts_[k]->value();
        l.degrees[k] = degrees_[k]->value();
        l.padding[k] = padding_[k]->value();
    }
    if (selectedPatches_->isChecked()) l.patches = selection_;
    return l;
}

std::optional<ffd::StationSpec> LatticeDialog::stations() const {
    if (!stationsBox_->isChecked()) return std::nullopt;
    ffd::StationSpec s;
    s.direction = direction_->currentIndex();
    // The paper's bit string per station is "zyx" (rightmost = X).
    const bool any = translate_[0]->isChecked() || translate_[1]->isChecked() || translate_[2]->isChecked();
    if (any) {
        std::string bits;
        for (int d = 2; d >= 0; --d) bits += translate_[static_cast<std::size_t>(d)]->isChecked() ? '1' : '0';
        s.bits.assign(static_cast<std::size_t>(counts_[static_cast<std::size_t>(s.direction)]->value()), bits);
    }
    s.translationBound = bound_->value();
    s.sectionScaling = scaling_->isChecked();
    s.taper = taper_->isChecked();
    s.vertical = 2;
    s.streamwise = 0;
    return s;
}

}  // namespace aero::ui
