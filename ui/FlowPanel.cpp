#include "FlowPanel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "OptionEditor.h"
#include "Resources.h"

namespace aero::ui {

namespace {

constexpr int kSliceSteps = 1000;

QString number(double v, int digits = 4) {
    if (std::isnan(v)) return QStringLiteral("NaN");
    return QLocale().toString(v, 'g', digits);
}

// The options the panel edits: section, key, label.
struct Shown {
    const char* section;
    const char* key;
    const char* label;
};
constexpr Shown kShown[] = {
    {"flow", "mach", "&Mach"},
    {"flow", "alpha", "&Angle of attack"},
    {"mesh", "level", "&Grid level"},
    {"mesh", "refine", "Grid &refinement"},
    {"flow", "kappa2", "Dissipation \u03ba&2"},
    {"flow", "kappa4", "Dissipation \u03ba&4"},
    {"flow", "max_iterations", "Max. &iterations"},
    {"flow", "tolerance", "&Tolerance"},
    {"flow", "max_seconds", "Time &limit (0: none)"},
};

}  // namespace

FlowPanel::FlowPanel(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("flowPanel"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(6, 6, 6, 6);

    // Case options.
    auto* caseBox = new QGroupBox(tr("Case"), this);
    auto* form = new QFormLayout(caseBox);
    form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    for (const Shown& s : kShown) {
        const std::string section = s.section, key = s.key;
        const io::OptionSpec& spec = section == "flow" ? io::findOption(io::flowOptions(), key).spec
                                                       : io::findOption(io::meshOptions(), key).spec;
        auto* editor = new OptionEditor(spec, caseBox);
        editor->widget()->setToolTip(QStringLiteral("<p><b>%1.%2</b></p>").arg(QString::fromStdString(section), QString::fromStdString(key)) +
                                     editor->widget()->toolTip() +
                                     tr("<p>An edit of the case (undoable); the next solve uses it.</p>"));
        form->addRow(tr(s.label), editor->widget());
        connect(editor, &OptionEditor::edited, this,
                [this, section, key](const io::OptionValue& v) { emit optionEdited(section, key, v); });
        rows_.push_back({section, key, editor});
    }
    layout->addWidget(caseBox);

    // Run.
    auto* runBox = new QGroupBox(tr("Solve"), this);
    auto* runLayout = new QVBoxLayout(runBox);
    auto* buttons = new QHBoxLayout;
    solve_ = new QPushButton(tr("Solve"), runBox);
    solve_->setObjectName(QStringLiteral("flowSolveButton"));
    solve_->setToolTip(tr("Solve the flow around the shape as shown: grid, mesh movement, Euler solution (F5)"));
    continue_ = new QPushButton(tr("Continue"), runBox);
    continue_->setMinimumWidth(continue_->sizeHint().width());
    continue_->setObjectName(QStringLiteral("flowContinueButton"));
    continue_->setToolTip(tr("Continue the run that was stopped, from the state it kept (its restart file)"));
    continue_->setEnabled(false);
    buttons->addWidget(solve_, 1);
    buttons->addWidget(continue_);
    runLayout->addLayout(buttons);
    // The status in a scroll area of its own: a failed solve's reason runs to a dozen lines (the
    // largest residual, the local Mach number, the wall's bend, the growing mode), one clause
    // per line; a plain label in the dock's layout was cut after four.
    auto* statusArea = new QScrollArea(runBox);
    statusArea->setObjectName(QStringLiteral("flowStatusArea"));
    statusArea->setWidgetResizable(true);
    statusArea->setFrameShape(QFrame::NoFrame);
    statusArea->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    statusText_ = tr("No solution yet.");
    status_ = new QLabel(statusText_);
    status_->setObjectName(QStringLiteral("flowStatus"));
    status_->setWordWrap(true);
    status_->setTextFormat(Qt::PlainText);
    status_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    status_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    statusArea->setWidget(status_);
    const int line = status_->fontMetrics().lineSpacing();
    statusArea->setMinimumHeight(3 * line + 4);
    statusArea->setMaximumHeight(10 * line + 4);
    runLayout->addWidget(statusArea);
    progress_ = new QLabel(runBox);
    progress_->setObjectName(QStringLiteral("flowProgress"));
    progress_->setWordWrap(true);
    progress_->setTextFormat(Qt::PlainText);
    progress_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    runLayout->addWidget(progress_);
    layout->addWidget(runBox);

    // Forces.
    forces_ = new QGroupBox(tr("Forces"), this);
    auto* grid = new QGridLayout(forces_);
    grid->setHorizontalSpacing(12);
    const std::pair<QString, QString> names[] = {
        {QStringLiteral("CL"), tr("C<sub>L</sub>")},          {QStringLiteral("CD"), tr("C<sub>D</sub>")},
        {QStringLiteral("CM"), tr("C<sub>M</sub>")},          {QStringLiteral("L/D"), tr("L/D")},
        {QStringLiteral("maxMach"), tr("Max. Mach")},        {QStringLiteral("maxEntropy"), tr("Max. |s \u2212 s\u221e|")}};
    int i = 0;
    for (const auto& [name, label] : names) {
        auto* title = new QLabel(label, forces_);
        title->setTextFormat(Qt::RichText);
        auto* value = new QLabel(QStringLiteral("\u2013"), forces_);
        value->setObjectName(QStringLiteral("flowForce_") + QString(name).replace(QLatin1Char('/'), QString()));
        value->setTextInteractionFlags(Qt::TextSelectableByMouse);
        value->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
        value->setMinimumWidth(value->fontMetrics().horizontalAdvance(QStringLiteral("-0.0000000")));
        grid->addWidget(title, i, 0);
        grid->addWidget(value, i, 1);
        forceLabels_.push_back({name, value});
        ++i;
    }
    forces_->setToolTip(tr("Coefficients of the force on the wall (the discrete momentum flux into it), over the "
                           "case's reference area and length. Lift and drag are normal to and along the free stream "
                           "in the X-Z plane; CM is the moment about +Y through the reference point. The largest "
                           "Mach number and entropy error are checks of the answer (the flow is subsonic and "
                           "isentropic where the scheme is exact)."));
    layout->addWidget(forces_);

    // Display.
    display_ = new QGroupBox(tr("Display"), this);
    auto* dform = new QFormLayout(display_);
    dform->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    field_ = new QComboBox(display_);
    field_->setObjectName(QStringLiteral("flowField"));
    for (int f = 0; f < kFlowFields; ++f) field_->addItem(QString::fromUtf8(flowFieldLabel(static_cast<FlowField>(f))), f);
    field_->setItemData(0, tr("s = (p/\u03c1^\u03b3)/(p\u221e/\u03c1\u221e^\u03b3) \u2212 1: zero in exact inviscid subsonic flow, so "
                              "every non-zero value is numerical error (the paper's Figure 6)"),
                        Qt::ToolTipRole);
    field_->setItemData(1, tr("Cp = (p \u2212 p\u221e)/(\u00bd \u03c1\u221e V\u221e\u00b2)"), Qt::ToolTipRole);
    field_->setItemData(2, tr("|u| / a, the local Mach number"), Qt::ToolTipRole);
    field_->setItemData(3, tr("p / (\u03c1\u221e a\u221e\u00b2): the free stream's is 1/\u03b3"), Qt::ToolTipRole);
    dform->addRow(tr("&Field"), field_);
    automatic_ = new QCheckBox(tr("Automatic"), display_);
    automatic_->setToolTip(tr("The field's range on the wall and the symmetry plane (for the entropy the 1st to 99th "
                              "percentile, since a few nodes at a blunt trailing edge would wash out the rest); "
                              "uncheck to choose one"));
    automatic_->setObjectName(QStringLiteral("flowRangeAutomatic"));
    automatic_->setChecked(true);
    dform->addRow(tr("Range"), automatic_);
    auto* rangeRow = new QHBoxLayout;
    lo_ = new NumberBox(display_);
    hi_ = new NumberBox(display_);
    for (NumberBox* b : {lo_, hi_}) {
        b->setRange(-1e300, 1e300);
        b->setEnabled(false);
        rangeRow->addWidget(b, 1);
    }
    lo_->setObjectName(QStringLiteral("flowRangeMin"));
    hi_->setObjectName(QStringLiteral("flowRangeMax"));
    rangeRow->insertWidget(1, new QLabel(QStringLiteral("\u2013"), display_));
    dform->addRow(QString(), rangeRow);
    auto* contourRow = new QHBoxLayout;
    contours_ = new QCheckBox(tr("Contour lines"), display_);
    contours_->setObjectName(QStringLiteral("flowContours"));
    contourCount_ = new QSpinBox(display_);
    contourCount_->setRange(1, 60);
    contourCount_->setValue(std::clamp(setting(QStringLiteral("flow/contourLevels")).toInt(), 1, 60));
    contourCount_->setSuffix(tr(" levels"));
    contourCount_->setEnabled(false);
    contourRow->addWidget(contours_);
    contourRow->addWidget(contourCount_, 1);
    dform->addRow(tr("Lines"), contourRow);
    auto* partRow = new QGridLayout;  // two by two: the dock is narrow
    for (auto [part, label, on] : {std::tuple{FlowPart::Wall, tr("Wall"), true}, std::tuple{FlowPart::Symmetry, tr("Symmetry"), true},
                                   std::tuple{FlowPart::Slice, tr("Slice"), false}, std::tuple{FlowPart::Sections, tr("Sections"), true}}) {
        auto* box = new QCheckBox(label, display_);
        box->setObjectName(QStringLiteral("flowPart%1").arg(static_cast<int>(part)));
        box->setChecked(on);
        partRow->addWidget(box, static_cast<int>(parts_.size()) / 2, static_cast<int>(parts_.size()) % 2);
        parts_.push_back({static_cast<int>(part), box});
        connect(box, &QCheckBox::toggled, this, [this, toggledPart = part](bool shown) { emit partToggled(toggledPart, shown); });
    }
    dform->addRow(tr("Show"), partRow);
    auto* sliceRow = new QHBoxLayout;
    sliceAxis_ = new QComboBox(display_);
    sliceAxis_->setObjectName(QStringLiteral("flowSliceAxis"));
    sliceAxis_->addItem(tr("x (streamwise)"), 0);
    sliceAxis_->addItem(tr("y (spanwise)"), 1);
    sliceAxis_->addItem(tr("z (vertical)"), 2);
    sliceAxis_->setToolTip(tr("The slice is the plane where this coordinate is constant"));
    sliceAxis_->setCurrentIndex(0);
    slicePosition_ = new QSlider(Qt::Horizontal, display_);
    slicePosition_->setObjectName(QStringLiteral("flowSlicePosition"));
    slicePosition_->setRange(0, kSliceSteps);
    slicePosition_->setValue(kSliceSteps / 2);
    slicePosition_->setToolTip(tr("Where the slice cuts the grid; moving it shows the slice"));
    sliceLabel_ = new QLabel(display_);
    sliceLabel_->setMinimumWidth(sliceLabel_->fontMetrics().horizontalAdvance(QStringLiteral("x = -00.000")));
    sliceRow->addWidget(sliceAxis_);
    sliceRow->addWidget(sliceLabel_);
    dform->addRow(tr("Slice"), sliceRow);
    dform->addRow(QString(), slicePosition_);
    layout->addWidget(display_);
    layout->addStretch(1);

    connect(solve_, &QPushButton::clicked, this, [this] {
        if (running_)
            emit stopRequested();
        else
            emit solveRequested();
    });
    connect(continue_, &QPushButton::clicked, this, &FlowPanel::continueRequested);
    connect(field_, &QComboBox::currentIndexChanged, this, [this] { emit fieldChanged(field()); });
    connect(automatic_, &QCheckBox::toggled, this, [this](bool on) {
        lo_->setEnabled(!on);
        hi_->setEnabled(!on);
        emitRange();
    });
    connect(lo_, &QDoubleSpinBox::valueChanged, this, [this] {
        if (!automatic_->isChecked()) emitRange();
    });
    connect(hi_, &QDoubleSpinBox::valueChanged, this, [this] {
        if (!automatic_->isChecked()) emitRange();
    });
    connect(contours_, &QCheckBox::toggled, this, [this](bool on) {
        contourCount_->setEnabled(on);
        emit contourCountChanged(contourCount());
    });
    connect(contourCount_, &QSpinBox::valueChanged, this, [this] { emit contourCountChanged(contourCount()); });
    connect(sliceAxis_, &QComboBox::currentIndexChanged, this, [this] { emitSlice(); });
    connect(slicePosition_, &QSlider::valueChanged, this, [this] {
        // Moving the slider means "show me the slice".
        for (auto& [part, box] : parts_)
            if (part == static_cast<int>(FlowPart::Slice) && !box->isChecked()) box->setChecked(true);
        emitSlice();
    });
    // The field shown first (settings: flow/field).
    const QString first = setting(QStringLiteral("flow/field")).toString();
    for (int f = 0; f < kFlowFields; ++f)
        if (first == QLatin1String(flowFieldKey(static_cast<FlowField>(f)))) field_->setCurrentIndex(f);
    updateSliceLabel();
    setResult(nullptr, false);
}

// ---- Case ---------------------------------------------------------------------------------------

void FlowPanel::setCase(const io::CaseFile& c) {
    for (Row& r : rows_) {
        const io::OptionValue v = r.section == "flow" ? io::findOption(io::flowOptions(), r.key).get(c.flow)
                                                      : io::findOption(io::meshOptions(), r.key).get(c.mesh);
        r.editor->setValue(v);
    }
}

OptionEditor* FlowPanel::editor(const std::string& section, const std::string& key) const {
    for (const Row& r : rows_)
        if (r.section == section && r.key == key) return r.editor;
    return nullptr;
}

// ---- Run ----------------------------------------------------------------------------------------

void FlowPanel::setRunning(bool running) {
    running_ = running;
    solve_->setText(running ? tr("Stop") : tr("Solve"));
    solve_->setToolTip(running ? tr("Stop the solve between iterations; the state reached is kept")
                               : tr("Solve the flow around the shape as shown: grid, mesh movement, Euler solution (F5)"));
    for (Row& r : rows_) r.editor->setEnabled(!running);
    continue_->setEnabled(!running && canContinue_);
    if (running) progress_->clear();
}

void FlowPanel::setCanContinue(bool can) {
    canContinue_ = can;
    continue_->setEnabled(!running_ && can);
}

void FlowPanel::setStatus(const QString& text, Tone tone) {
    // One clause of a reason per line (its parts are joined by "; ").
    QString shown = text;
    shown.replace(QStringLiteral("; "), QStringLiteral(";\n"));
    status_->setText(shown);
    status_->setToolTip(text);
    statusText_ = text;
    const char* colour = tone == Tone::Busy      ? "#1f4e9a"
                         : tone == Tone::Good    ? "#1d6b2f"
                         : tone == Tone::Warning ? "#a05a00"
                         : tone == Tone::Bad     ? "#b00020"
                                                 : nullptr;
    status_->setStyleSheet(colour ? QStringLiteral("QLabel { color: %1; font-weight: bold; }").arg(QLatin1String(colour))
                                  : QString());
}

QString FlowPanel::statusText() const {
    return statusText_;
}

void FlowPanel::setProgress(const QString& text) {
    progress_->setText(text);
}

// ---- Result -------------------------------------------------------------------------------------

void FlowPanel::setResult(std::shared_ptr<const FlowRunResult> result, bool outdated) {
    result_ = std::move(result);
    const study::FlowResult* f = result_ ? result_->flow.get() : nullptr;
    auto set = [this](const QString& name, const QString& text) {
        if (QLabel* l = forceLabel(name)) l->setText(text);
    };
    if (!f) {
        for (auto& [name, label] : forceLabels_) label->setText(QStringLiteral("\u2013"));
    } else {
        const flow::ForceCoefficients& c = f->forces;
        set(QStringLiteral("CL"), number(c.CL, 6));
        set(QStringLiteral("CD"), number(c.CD, 6));
        set(QStringLiteral("CM"), number(c.CM, 6));
        set(QStringLiteral("L/D"), std::abs(c.CD) > 1e-300 ? number(c.CL / c.CD, 4) : QStringLiteral("\u2013"));
        set(QStringLiteral("maxMach"), number(f->maxMach.value, 4));
        set(QStringLiteral("maxEntropy"), number(std::abs(f->maxEntropy.value), 3));
        if (QLabel* l = forceLabel(QStringLiteral("maxMach")))
            l->setToolTip(tr("at block %1 \u2018%2\u2019 node (%3, %4, %5), %6")
                              .arg(f->maxMach.block)
                              .arg(QString::fromStdString(f->maxMach.blockName))
                              .arg(f->maxMach.node[0])
                              .arg(f->maxMach.node[1])
                              .arg(f->maxMach.node[2])
                              .arg(QString::fromStdString(f->maxMach.boundary)));
    }
    forces_->setEnabled(f && !outdated);
    display_->setEnabled(f && !outdated);
}

QLabel* FlowPanel::forceLabel(const QString& name) const {
    for (const auto& [n, label] : forceLabels_)
        if (n == name) return label;
    return nullptr;
}

// ---- Display ------------------------------------------------------------------------------------

FlowField FlowPanel::field() const {
    return static_cast<FlowField>(std::clamp(field_->currentIndex(), 0, kFlowFields - 1));
}

void FlowPanel::setField(FlowField field) {
    field_->setCurrentIndex(static_cast<int>(field));
}

void FlowPanel::setAutomaticRange(std::pair<double, double> range) {
    if (!automatic_->isChecked()) return;
    const QSignalBlocker a(lo_), b(hi_);
    lo_->setValue(range.first);
    hi_->setValue(range.second);
}

bool FlowPanel::automaticRange() const {
    return automatic_->isChecked();
}

std::pair<double, double> FlowPanel::chosenRange() const {
    return {lo_->value(), hi_->value()};
}

void FlowPanel::setChosenRange(std::pair<double, double> range) {
    {
        const QSignalBlocker a(lo_), b(hi_), c(automatic_);
        lo_->setValue(range.first);
        hi_->setValue(range.second);
        automatic_->setChecked(false);
        lo_->setEnabled(true);
        hi_->setEnabled(true);
    }
    emitRange();
}

void FlowPanel::emitRange() {
    emit rangeChanged(automatic_->isChecked(), lo_->value(), hi_->value());
}

bool FlowPanel::partShown(FlowPart part) const {
    for (const auto& [p, box] : parts_)
        if (p == static_cast<int>(part)) return box->isChecked();
    return part == FlowPart::Contours ? contours_->isChecked() : false;
}

void FlowPanel::setPartShown(FlowPart part, bool shown) {
    for (auto& [p, box] : parts_)
        if (p == static_cast<int>(part)) box->setChecked(shown);
    if (part == FlowPart::Contours) contours_->setChecked(shown);
}

int FlowPanel::contourCount() const {
    return contours_->isChecked() ? contourCount_->value() : 0;
}

int FlowPanel::sliceAxis() const {
    return sliceAxis_->currentData().toInt();
}

double FlowPanel::slicePosition() const {
    const int a = sliceAxis();
    const double lo = bounds_[static_cast<std::size_t>(2 * a)], hi = bounds_[static_cast<std::size_t>(2 * a + 1)];
    return lo + (hi - lo) * slicePosition_->value() / static_cast<double>(kSliceSteps);
}

void FlowPanel::setSliceBounds(const std::array<double, 6>& bounds) {
    bounds_ = bounds;
    updateSliceLabel();
}

void FlowPanel::setSlice(int axis, double position) {
    const QSignalBlocker a(sliceAxis_), b(slicePosition_);
    sliceAxis_->setCurrentIndex(std::clamp(axis, 0, 2));
    const double lo = bounds_[static_cast<std::size_t>(2 * axis)], hi = bounds_[static_cast<std::size_t>(2 * axis + 1)];
    slicePosition_->setValue(hi > lo ? static_cast<int>(std::lround((position - lo) / (hi - lo) * kSliceSteps)) : kSliceSteps / 2);
    updateSliceLabel();
}

void FlowPanel::emitSlice() {
    updateSliceLabel();
    emit sliceChanged(sliceAxis(), slicePosition());
}

void FlowPanel::updateSliceLabel() {
    sliceLabel_->setText(QStringLiteral("%1 = %2").arg(QString(QLatin1Char("xyz"[sliceAxis()])), number(slicePosition(), 3)));
}

}  // namespace aero::ui
