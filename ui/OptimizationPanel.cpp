#include "OptimizationPanel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLocale>
#include <QPainter>
#include <QPlainTextEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QStyledItemDelegate>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "OptionEditor.h"

namespace aero::ui {

namespace {

constexpr int kLogLines = 400;
constexpr int kValueRole = Qt::UserRole + 1;  // dJ/dv of a sensitivity row (sorting, bar)
constexpr int kScaleRole = Qt::UserRole + 2;  // the largest |dJ/dv| (the bar's full length)

// The options the panel edits, in its order, with their labels.
struct Shown {
    const char* key;
    const char* label;
};
constexpr Shown kProblem[] = {
    {"objective", "&Objective"},
    {"sense", "&Sense"},
    {"optimizer", "O&ptimizer"},
    {"max_evaluations", "Max. &evaluations"},
    {"max_iterations", "Max. &iterations"},
    {"optimality_tolerance", "Optimality tol."},
    {"feasibility_tolerance", "Feasibility tol."},
    {"objective_scale", "Objective scale"},
    {"variable_scaling", "Variable scaling"},
};
constexpr Shown kConstraints[] = {
    {"lift_constraint", "Keep &CL"},
    {"target_cl", "Target CL"},
    {"min_corner_ratio", "Grid corner ratio \u2265"},
    {"max_wall_bend", "Wall bend \u2264"},
    {"max_wall_mach", "Wall Mach \u2264"},
    {"alpha_variable", "&Alpha a variable"},
    {"alpha_lower", "Alpha from"},
    {"alpha_upper", "Alpha to"},
};

// A signed horizontal bar in the sensitivity list: to the right of the centre for dJ/dv > 0
// (blue), to the left for < 0 (orange), its length |dJ/dv| over the largest.
class BarDelegate : public QStyledItemDelegate {
  public:
    using QStyledItemDelegate::QStyledItemDelegate;
    void paint(QPainter* p, const QStyleOptionViewItem& option,
               const QModelIndex& index) const override {
        QStyledItemDelegate::paint(p, option, QModelIndex());  // background and selection only
        const double v = index.data(kValueRole).toDouble(),
                     scale = index.data(kScaleRole).toDouble();
        const QRectF r = QRectF(option.rect).adjusted(4, 3, -4, -3);
        const double mid = r.center().x();
        p->save();
        p->setPen(QPen(QColor(150, 154, 164), 1));
        p->drawLine(QPointF(mid, r.top() - 2), QPointF(mid, r.bottom() + 2));
        if (scale > 0 && std::isfinite(v)) {
            const double w = 0.5 * r.width() * std::min(1.0, std::abs(v) / scale);
            const QRectF bar = v >= 0 ? QRectF(mid, r.top(), w, r.height())
                                      : QRectF(mid - w, r.top(), w, r.height());
            p->fillRect(bar, v >= 0 ? QColor(52, 100, 186) : QColor(222, 128, 34));
        }
        p->restore();
    }
    QSize sizeHint(const QStyleOptionViewItem& option, const QModelIndex& index) const override {
        return QStyledItemDelegate::sizeHint(option, index).expandedTo(QSize(120, 16));
    }
};

// Sorts the sensitivity rows by their value (column 1) rather than by the text.
class SensitivityItem : public QTreeWidgetItem {
  public:
    using QTreeWidgetItem::QTreeWidgetItem;
    bool operator<(const QTreeWidgetItem& other) const override {
        const int c = treeWidget() ? treeWidget()->sortColumn() : 0;
        if (c == 1 || c == 2)
            return data(1, kValueRole).toDouble() < other.data(1, kValueRole).toDouble();
        return QTreeWidgetItem::operator<(other);
    }
};

}  // namespace

OptimizationPanel::OptimizationPanel(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("optimizationPanel"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(6, 6, 6, 6);

    // Problem.
    auto* problem = new QGroupBox(tr("Problem"), this);
    auto* form = new QFormLayout(problem);
    form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    note_ = new QLabel(problem);
    note_->setWordWrap(true);
    note_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    form->addRow(note_);
    auto addEditor = [this](QFormLayout* f, QWidget* owner, const Shown& s) {
        const std::string key = s.key;
        auto* e = new OptionEditor(io::findOption(io::optimizationOptions(), key).spec, owner);
        e->widget()->setToolTip(
            QStringLiteral("<p><b>optimization.%1</b></p>").arg(QString::fromStdString(key)) +
            e->widget()->toolTip() +
            tr("<p>An edit of the case (undoable); the next run uses it.</p>"));
        f->addRow(tr(s.label), e->widget());
        connect(e, &OptionEditor::edited, this,
                [this, key](const io::OptionValue& v) { emit optionEdited(key, v); });
        rows_.push_back({key, e});
    };
    for (const Shown& s : kProblem) addEditor(form, problem, s);
    // The start: the case's own design or another case's (optimization.start_design), e.g. a
    // coarser grid's best evaluation written with aeroform-cli optimize --design N.
    auto* startRow = new QVBoxLayout;  // the file's name above its buttons: the dock is narrow
    auto* startButtons = new QHBoxLayout;
    startDesign_ = new QLabel(problem);
    startDesign_->setObjectName(QStringLiteral("optimizationStartDesign"));
    startDesign_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    startDesign_->setWordWrap(true);
    chooseStart_ = new QPushButton(tr("Choose a Case\u2026"), problem);
    chooseStart_->setObjectName(QStringLiteral("optimizationChooseStart"));
    clearStart_ = new QPushButton(tr("Its Own Design"), problem);
    clearStart_->setObjectName(QStringLiteral("optimizationClearStart"));
    const QString startTip =
        tr("<p><b>optimization.start_design</b></p><p>The design the optimizer starts from: this "
           "case's own, or the design values (and alpha, when it is a variable) of another case "
           "file, e.g. a coarser grid's best evaluation written with <tt>aeroform-cli optimize "
           "--design N</tt>. Only the start moves: the bounds, the constraints and the volume "
           "\u2265 the start's still refer to this case's own design.</p>"
           "<p>An edit of the case (undoable); the next run uses it.</p>");
    chooseStart_->setToolTip(startTip);  // the label's: setCase (with the file's path)
    clearStart_->setToolTip(tr("<p>Start from this case's own design (no start_design).</p>"));
    startRow->addWidget(startDesign_);
    startButtons->addWidget(chooseStart_);
    startButtons->addWidget(clearStart_);
    startButtons->addStretch(1);
    startRow->addLayout(startButtons);
    form->addRow(tr("Start from"), startRow);
    connect(chooseStart_, &QPushButton::clicked, this, &OptimizationPanel::startDesignChooseRequested);
    connect(clearStart_, &QPushButton::clicked, this, [this] { emit startDesignEdited(QString()); });

    auto* constraints = new QGroupBox(tr("Constraints"), this);
    auto* cform = new QFormLayout(constraints);
    cform->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    auto* volumeRow = new QHBoxLayout;
    volume_ = new QComboBox(constraints);
    volume_->setObjectName(QStringLiteral("optimizationVolume"));
    volume_->addItem(tr("Free"));
    volume_->addItem(tr("\u2265 the start's"));
    volume_->addItem(tr("\u2265 value"));
    volume_->setToolTip(
        tr("<p><b>constraints.min_volume</b></p><p>The enclosed volume stays at least the start's "
           "(the paper's sphere-to-wing problem) or a given value, with its exact gradient.</p>"));
    volumeValue_ = new NumberBox(constraints);
    volumeValue_->setRange(1e-12, 1e12);
    volumeValue_->setValue(1.0);
    volumeValue_->setEnabled(false);
    volumeRow->addWidget(volume_, 1);
    volumeRow->addWidget(volumeValue_, 1);
    cform->addRow(tr("&Volume"), volumeRow);
    connect(volume_, &QComboBox::activated, this, [this] {
        volumeValue_->setEnabled(volume_->currentIndex() == 2);
        emitVolume();
    });
    connect(volumeValue_, &QDoubleSpinBox::editingFinished, this, [this] {
        if (volume_->currentIndex() == 2) emitVolume();
    });
    for (const Shown& s : kConstraints) addEditor(cform, constraints, s);
    linear_ = new QLabel(constraints);
    linear_->setWordWrap(true);
    linear_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    cform->addRow(tr("Linear"), linear_);

    // Run.
    auto* run = new QGroupBox(tr("Run"), this);
    auto* runLayout = new QVBoxLayout(run);
    auto* buttons = new QGridLayout;  // two by two: the panel fits a narrow dock
    start_ = new QPushButton(tr("Start"), run);
    start_->setObjectName(QStringLiteral("optimizationStart"));
    pause_ = new QPushButton(tr("Pause"), run);
    pause_->setObjectName(QStringLiteral("optimizationPause"));
    pause_->setToolTip(tr(
        "Pause after the evaluation (or gradient) being computed: the history then ends on a whole "
        "record and Resume continues exactly where it stopped"));
    stop_ = new QPushButton(tr("Stop"), run);
    stop_->setObjectName(QStringLiteral("optimizationStop"));
    stop_->setToolTip(
        tr("Stop within the current flow iteration; the evaluation it interrupts is solved again "
           "on Resume"));
    resume_ = new QPushButton(tr("Resume"), run);
    resume_->setObjectName(QStringLiteral("optimizationResume"));
    resume_->setToolTip(tr(
        "Continue the history: what it holds is replayed to the optimizer (not solved again), bit "
        "for bit, then the run goes on"));
    int at = 0;
    for (QPushButton* b : {start_, resume_, pause_, stop_}) {
        b->setEnabled(false);
        buttons->addWidget(b, at / 2, at % 2);
        ++at;
    }
    runLayout->addLayout(buttons);
    connect(start_, &QPushButton::clicked, this,
            [this] { startIsStartOver_ ? emit startOverRequested() : emit startRequested(); });
    connect(pause_, &QPushButton::clicked, this, &OptimizationPanel::pauseRequested);
    connect(stop_, &QPushButton::clicked, this, &OptimizationPanel::stopRequested);
    connect(resume_, &QPushButton::clicked, this, &OptimizationPanel::resumeRequested);
    status_ = new QLabel(tr("Not run yet."), run);
    status_->setObjectName(QStringLiteral("optimizationStatus"));
    status_->setWordWrap(true);
    status_->setTextFormat(Qt::PlainText);
    status_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    status_->setMinimumHeight(2 * status_->fontMetrics().lineSpacing() + 4);
    status_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    runLayout->addWidget(status_);
    progress_ = new QLabel(run);
    progress_->setObjectName(QStringLiteral("optimizationProgress"));
    progress_->setWordWrap(true);
    progress_->setTextFormat(Qt::PlainText);
    progress_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    runLayout->addWidget(progress_);
    log_ = new QPlainTextEdit(run);
    log_->setObjectName(QStringLiteral("optimizationLog"));
    log_->setReadOnly(true);
    log_->setMaximumBlockCount(kLogLines);
    log_->setLineWrapMode(QPlainTextEdit::NoWrap);
    log_->setFixedHeight(6 * log_->fontMetrics().lineSpacing());
    QFont mono = log_->font();
    mono.setStyleHint(QFont::Monospace);
    mono.setFamily(QStringLiteral("monospace"));
    mono.setPointSizeF(std::max(7.0, mono.pointSizeF() - 1));
    log_->setFont(mono);
    log_->setToolTip(
        tr("The optimizer's log: evaluations, gradients and iterations as `aeroform-cli optimize` "
           "prints them"));
    runLayout->addWidget(log_);

    // Evaluation (the history slider).
    auto* eval = new QGroupBox(tr("Evaluation"), this);
    auto* evalLayout = new QVBoxLayout(eval);
    auto* sliderRow = new QHBoxLayout;
    slider_ = new QSlider(Qt::Horizontal, eval);
    slider_->setObjectName(QStringLiteral("optimizationHistorySlider"));
    slider_->setRange(0, 0);
    slider_->setPageStep(1);
    slider_->setToolTip(
        tr("Brings back any evaluation: its numbers, shape, lattices and (when kept) flow fields"));
    slider_->setEnabled(false);
    sliderLabel_ = new QLabel(tr("\u2013"), eval);
    sliderLabel_->setMinimumWidth(
        sliderLabel_->fontMetrics().horizontalAdvance(QStringLiteral("999 of 999")));
    sliderRow->addWidget(slider_, 1);
    sliderRow->addWidget(sliderLabel_);
    evalLayout->addLayout(sliderRow);
    connect(slider_, &QSlider::valueChanged, this, [this](int v) {
        sliderLabel_->setText(v > 0 ? tr("%1 of %2").arg(v).arg(slider_->maximum())
                                    : QStringLiteral("\u2013"));
        if (follow_->isChecked() && v != slider_->maximum()) {
            const QSignalBlocker block(follow_);
            follow_->setChecked(false);  // the user went back: stay there
        }
        emit evaluationChosen(v);
    });
    auto* checks = new QHBoxLayout;
    follow_ = new QCheckBox(tr("Follow the run"), eval);
    follow_->setObjectName(QStringLiteral("optimizationFollow"));
    follow_->setChecked(true);
    follow_->setToolTip(tr("Show each new evaluation as it is recorded"));
    view_ = new QCheckBox(tr("Show in 3D view"), eval);
    view_->setObjectName(QStringLiteral("optimizationView"));
    view_->setToolTip(
        tr("The evaluation takes the 3D view; uncheck to see the project's own design"));
    checks->addWidget(follow_);
    checks->addWidget(view_);
    checks->addStretch(1);
    evalLayout->addLayout(checks);
    connect(follow_, &QCheckBox::toggled, this, &OptimizationPanel::followToggled);
    connect(view_, &QCheckBox::toggled, this, &OptimizationPanel::viewToggled);
    evaluation_ = new QLabel(tr("No evaluations yet."), eval);
    evaluation_->setObjectName(QStringLiteral("optimizationEvaluation"));
    evaluation_->setWordWrap(true);
    evaluation_->setTextFormat(Qt::PlainText);
    evaluation_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    evalLayout->addWidget(evaluation_);
    auto* eform = new QFormLayout;
    eform->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    field_ = new QComboBox(eval);
    field_->setObjectName(QStringLiteral("optimizationField"));
    for (int f = 0; f < kFlowFields; ++f)
        field_->addItem(QString::fromUtf8(flowFieldLabel(static_cast<FlowField>(f))), f);
    eform->addRow(tr("Field"), field_);
    connect(field_, &QComboBox::currentIndexChanged, this,
            [this](int i) { emit fieldChanged(static_cast<FlowField>(i)); });
    auto* compareRow = new QHBoxLayout;
    compare_ = new QSpinBox(eval);
    compare_->setObjectName(QStringLiteral("optimizationCompare"));
    compare_->setRange(0, 0);
    compare_->setSpecialValueText(tr("none"));
    compare_->setToolTip(tr("A second evaluation to compare with the one shown"));
    compareMode_ = new QComboBox(eval);
    compareMode_->setObjectName(QStringLiteral("optimizationCompareMode"));
    compareMode_->addItem(tr("Side by side"), static_cast<int>(CompareMode::SideBySide));
    compareMode_->addItem(tr("Overlaid"), static_cast<int>(CompareMode::Overlay));
    compareRow->addWidget(compare_, 1);
    compareRow->addWidget(compareMode_, 1);
    eform->addRow(tr("Compare with"), compareRow);
    auto emitCompare = [this] { emit compareChanged(comparedEvaluation(), compareMode()); };
    connect(compare_, &QSpinBox::valueChanged, this, emitCompare);
    connect(compareMode_, &QComboBox::currentIndexChanged, this, emitCompare);
    evalLayout->addLayout(eform);
    auto* evalButtons = new QGridLayout;
    use_ = new QPushButton(tr("Use This Design"), eval);
    use_->setObjectName(QStringLiteral("optimizationUseDesign"));
    use_->setToolTip(tr("The project takes this evaluation's design values (one undoable edit)"));
    solveFlow_ = new QPushButton(tr("Solve Its Flow"), eval);
    solveFlow_->setObjectName(QStringLiteral("optimizationSolveFlow"));
    solveFlow_->setToolTip(
        tr("This evaluation's solution is not kept (replayed, read back or dropped for memory): "
           "solve its flow again to see its fields"));
    exportShape_ = new QPushButton(tr("Export IGES..."), eval);
    exportShape_->setObjectName(QStringLiteral("optimizationExportShape"));
    exportShape_->setToolTip(tr("This evaluation's shape as exact IGES (17 digits)"));
    at = 0;
    for (QPushButton* b : {use_, solveFlow_, exportShape_}) {
        b->setEnabled(false);
        evalButtons->addWidget(b, at / 2, at % 2);
        ++at;
    }
    evalLayout->addLayout(evalButtons);
    connect(use_, &QPushButton::clicked, this, &OptimizationPanel::useDesignRequested);
    connect(solveFlow_, &QPushButton::clicked, this, &OptimizationPanel::solveFlowRequested);
    connect(exportShape_, &QPushButton::clicked, this, &OptimizationPanel::exportShapeRequested);
    // The run and its evaluations first (what is watched while it works), the problem below.
    layout->insertWidget(0, run);
    layout->insertWidget(1, eval);
    layout->addWidget(problem);
    layout->addWidget(constraints);

    // Files.
    auto* files = new QGroupBox(tr("Files"), this);
    auto* filesLayout = new QVBoxLayout(files);
    history_ = new QLabel(files);
    history_->setObjectName(QStringLiteral("optimizationHistoryPath"));
    history_->setWordWrap(true);
    history_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    history_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    filesLayout->addWidget(history_);
    auto* fileButtons = new QHBoxLayout;
    auto* exportHistory = new QPushButton(tr("Export History..."), files);
    exportHistory->setObjectName(QStringLiteral("optimizationExportHistory"));
    exportHistory->setToolTip(
        tr("The history as CSV (every evaluation and gradient; the major iterations beside it) "
           "and its exact JSON lines"));
    auto* exportPlots = new QPushButton(tr("Export Plots..."), files);
    exportPlots->setObjectName(QStringLiteral("optimizationExportPlots"));
    exportPlots->setToolTip(tr("Every plot as PNG and SVG, with its data as CSV, into a folder"));
    fileButtons->addWidget(exportHistory);
    fileButtons->addWidget(exportPlots);
    filesLayout->addLayout(fileButtons);
    connect(exportHistory, &QPushButton::clicked, this, &OptimizationPanel::exportHistoryRequested);
    connect(exportPlots, &QPushButton::clicked, this, &OptimizationPanel::exportPlotsRequested);
    layout->addWidget(files);

    // Sensitivities.
    auto* sens = new QGroupBox(tr("Design sensitivities"), this);
    auto* sensLayout = new QVBoxLayout(sens);
    sensitivityNote_ = new QLabel(
        tr("dJ/dv of every design variable appears here after the first gradient."), sens);
    sensitivityNote_->setWordWrap(true);
    sensitivityNote_->setStyleSheet(QStringLiteral("QLabel { color: #505868; }"));
    sensLayout->addWidget(sensitivityNote_);
    sensitivities_ = new QTreeWidget(sens);
    sensitivities_->setObjectName(QStringLiteral("optimizationSensitivities"));
    sensitivities_->setColumnCount(3);
    sensitivities_->setHeaderLabels({tr("Variable"), tr("dJ/dv"), tr("")});
    sensitivities_->setRootIsDecorated(false);
    sensitivities_->setSortingEnabled(true);
    sensitivities_->setItemDelegateForColumn(2, new BarDelegate(sensitivities_));
    sensitivities_->header()->setStretchLastSection(true);
    sensitivities_->setMinimumHeight(160);
    sensitivities_->setToolTip(
        tr("Click a header to sort: by name, or by the signed derivative (the bar: blue raises "
           "J, orange lowers it, as the variable grows)"));
    sensLayout->addWidget(sensitivities_);
    layout->addWidget(sens);
    layout->addStretch(1);
}

// ---- Case
// -----------------------------------------------------------------------------------------

void OptimizationPanel::setCase(const io::CaseFile& c, const QString& historyPath) {
    const io::OptimizationCase& oc = c.optimization;
    for (Row& r : rows_)
        r.editor->setValue(io::findOption(io::optimizationOptions(), r.key).get(oc));
    note_->setText(oc.present ? tr("The case's optimization section; edits are undoable.")
                              : tr("The case has no optimization yet: any choice below adds one "
                                   "(the defaults shown)."));
    {
        const QSignalBlocker block(volume_);
        volume_->setCurrentIndex(!c.minVolume ? 0 : std::isnan(*c.minVolume) ? 1 : 2);
        if (c.minVolume && !std::isnan(*c.minVolume)) volumeValue_->setValue(*c.minVolume);
        volumeValue_->setEnabled(volume_->currentIndex() == 2);
    }
    QStringList linear;
    if (c.symmetry) linear << tr("symmetric across Y = 0");
    if (c.stationGap) linear << tr("adjacent stations at least %1 apart").arg(*c.stationGap);
    if (c.stationSecondDifference) {
        linear << tr("lattice bent by at most %1 between three stations").arg(*c.stationSecondDifference);
    }
    linear_->setText(linear.isEmpty() ? tr("none") : linear.join(QStringLiteral("; ")));
    if (oc.startDesign.empty()) {
        startDesign_->setText(tr("this case's design"));
        startDesign_->setToolTip(chooseStart_->toolTip());
    } else {
        const QString path = QString::fromStdString(oc.startDesign);
        startDesign_->setText(QFileInfo(path).fileName());
        startDesign_->setToolTip(QStringLiteral("<p>%1</p>").arg(path.toHtmlEscaped()) + chooseStart_->toolTip());
    }
    clearStart_->setEnabled(!oc.startDesign.empty());
    history_->setText(historyPath.isEmpty()
                          ? tr("History: none yet (save the project: it is kept beside it).")
                          : tr("History: %1").arg(historyPath));
}

OptionEditor* OptimizationPanel::editor(const std::string& key) const {
    for (const Row& r : rows_)
        if (r.key == key) return r.editor;
    return nullptr;
}

void OptimizationPanel::emitVolume() {
    switch (volume_->currentIndex()) {
        case 0:
            emit volumeEdited(std::nullopt);
            break;
        case 1:
            emit volumeEdited(std::nan(""));
            break;
        default:
            emit volumeEdited(volumeValue_->value());
            break;
    }
}

// ---- Run
// ------------------------------------------------------------------------------------------

void OptimizationPanel::setRunState(const QString& text, Tone tone, const Actions& can,
                                    bool running) {
    status_->setText(text);
    const char* colour = tone == Tone::Busy      ? "#1f4e9a"
                         : tone == Tone::Good    ? "#1d6b2f"
                         : tone == Tone::Warning ? "#a05a00"
                         : tone == Tone::Bad     ? "#b00020"
                                                 : nullptr;
    status_->setStyleSheet(
        colour
            ? QStringLiteral("QLabel { color: %1; font-weight: bold; }").arg(QLatin1String(colour))
            : QString());
    startIsStartOver_ = can.startOver;
    start_->setText(can.startOver ? tr("Start Over") : tr("Start"));
    start_->setToolTip(
        can.startOver
            ? tr("Start a new run from the case's design, replacing the history (asks first)")
            : tr("Run the case's optimization: each evaluation a flow solve, each gradient an "
                 "adjoint; the history is written as it runs"));
    start_->setEnabled(can.start || can.startOver);
    pause_->setEnabled(can.pause);
    stop_->setEnabled(can.stop);
    resume_->setEnabled(can.resume);
    for (Row& r : rows_) r.editor->setEnabled(!running);
    volume_->setEnabled(!running);
    volumeValue_->setEnabled(!running && volume_->currentIndex() == 2);
    if (!running) progress_->clear();
}

QString OptimizationPanel::statusText() const {
    return status_->text();
}

void OptimizationPanel::setProgress(const QString& text) {
    progress_->setText(text);
}

void OptimizationPanel::appendLog(const QString& line) {
    log_->appendPlainText(line);
}

void OptimizationPanel::clearLog() {
    log_->clear();
}

// ---- Evaluation
// -------------------------------------------------------------------------------------

void OptimizationPanel::setEvaluationCount(int count) {
    const QSignalBlocker block(slider_);
    const int at = slider_->value();
    slider_->setRange(count > 0 ? 1 : 0, count);
    slider_->setEnabled(count > 1);
    if (at > count || at < 1) slider_->setValue(count);
    sliderLabel_->setText(slider_->value() > 0 ? tr("%1 of %2").arg(slider_->value()).arg(count)
                                               : QStringLiteral("\u2013"));
    const QSignalBlocker blockCompare(compare_);
    compare_->setRange(0, count);
}

int OptimizationPanel::evaluationCount() const {
    return slider_->maximum();
}

void OptimizationPanel::setCurrentEvaluation(int index) {
    const QSignalBlocker block(slider_);
    slider_->setValue(index);
    sliderLabel_->setText(slider_->value() > 0
                              ? tr("%1 of %2").arg(slider_->value()).arg(slider_->maximum())
                              : QStringLiteral("\u2013"));
}

int OptimizationPanel::currentEvaluation() const {
    return slider_->value();
}

void OptimizationPanel::setEvaluationText(const QString& text, bool failed) {
    evaluation_->setText(text);
    evaluation_->setStyleSheet(failed ? QStringLiteral("QLabel { color: #b00020; }") : QString());
}

QString OptimizationPanel::evaluationText() const {
    return evaluation_->text();
}

void OptimizationPanel::setEvaluationActions(bool canUse, bool canSolveFlow, bool canExport) {
    use_->setEnabled(canUse);
    solveFlow_->setEnabled(canSolveFlow);
    exportShape_->setEnabled(canExport);
}

bool OptimizationPanel::follow() const {
    return follow_->isChecked();
}

void OptimizationPanel::setFollow(bool on) {
    const QSignalBlocker block(follow_);
    follow_->setChecked(on);
}

bool OptimizationPanel::viewShown() const {
    return view_->isChecked();
}

void OptimizationPanel::setViewShown(bool on) {
    const QSignalBlocker block(view_);
    view_->setChecked(on);
}

int OptimizationPanel::comparedEvaluation() const {
    return compare_->value();
}

void OptimizationPanel::setComparedEvaluation(int index) {
    compare_->setValue(index);
}

CompareMode OptimizationPanel::compareMode() const {
    return static_cast<CompareMode>(compareMode_->currentData().toInt());
}

void OptimizationPanel::setCompareMode(CompareMode mode) {
    compareMode_->setCurrentIndex(std::max(0, compareMode_->findData(static_cast<int>(mode))));
}

FlowField OptimizationPanel::field() const {
    return static_cast<FlowField>(field_->currentIndex());
}

// ---- Sensitivities
// -----------------------------------------------------------------------------------

void OptimizationPanel::setSensitivities(const std::vector<std::string>& names,
                                         const std::vector<double>& dJdv, const QString& note) {
    sensitivityNote_->setText(note);
    const int sortColumn = sensitivities_->sortColumn();
    const Qt::SortOrder order = sensitivities_->header()->sortIndicatorOrder();
    sensitivities_->setSortingEnabled(false);
    sensitivities_->clear();
    double largest = 0;
    for (double v : dJdv)
        if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
    for (std::size_t i = 0; i < names.size() && i < dJdv.size(); ++i) {
        auto* item = new SensitivityItem(sensitivities_);
        item->setText(0, QString::fromStdString(names[i]));
        item->setText(1, QLocale().toString(dJdv[i], 'g', 4));
        item->setData(1, kValueRole, dJdv[i]);
        item->setData(2, kValueRole, dJdv[i]);
        item->setData(2, kScaleRole, largest);
        item->setTextAlignment(1, Qt::AlignRight | Qt::AlignVCenter);
    }
    sensitivities_->setSortingEnabled(true);
    sensitivities_->sortByColumn(sortColumn < 0 ? 0 : sortColumn, order);
    sensitivities_->resizeColumnToContents(0);
    sensitivities_->resizeColumnToContents(1);
}

}  // namespace aero::ui
