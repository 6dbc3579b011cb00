#include "MeshPanel.h"

#include <QComboBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "QualityHistogram.h"
#include "io/Options.h"
#include "study/CaseEvaluator.h"
#include "Text.h"

namespace aero::ui {

namespace {

QString number(double v, int digits = 3) {
    if (std::isnan(v)) return QStringLiteral("NaN");
    if (std::isinf(v)) return v > 0 ? QStringLiteral("\u221e") : QStringLiteral("\u2212\u221e");
    return QLocale().toString(v, 'g', digits);
}

QString count(long long n) {
    return QLocale().toString(n);
}

}  // namespace

MeshPanel::MeshPanel(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("meshPanel"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(6, 6, 6, 6);

    // Grid: options and the run button.
    auto* grid = new QGroupBox(tr("Grid"), this);
    auto* gridLayout = new QVBoxLayout(grid);
    auto* form = new QFormLayout;
    form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    level_ = new QComboBox(grid);
    level_->setObjectName(QStringLiteral("meshLevel"));
    level_->addItem(tr("Coarse"), QStringLiteral("coarse"));
    level_->addItem(tr("Medium"), QStringLiteral("medium"));
    level_->addItem(tr("Paper"), QStringLiteral("paper"));
    level_->setItemData(
        0, tr("17 x 17 x 17 nodes per block, wall spacing 0.01: 98,260 nodes on the half-sphere, the optimization grid (seconds)"),
        Qt::ToolTipRole);
    level_->setItemData(1, tr("23 x 23 x 29 nodes per block, wall spacing 0.001: 306,820 nodes on the half-sphere"),
                        Qt::ToolTipRole);
    level_->setItemData(
        2, tr("The paper's grid, 31 x 31 x 47 nodes per block, wall spacing 0.001: 903,340 nodes (a minute or more)"),
        Qt::ToolTipRole);
    level_->setToolTip(
        tr("Grid level of the case (mesh.level); resets the grid options to the level's defaults. "
           "Undoable."));
    form->addRow(tr("&Level"), level_);
    increments_ = new QSpinBox(grid);
    increments_->setObjectName(QStringLiteral("meshIncrements"));
    // Range and description from the case file's option table: the panel accepts what the case
    // parser accepts.
    const io::OptionSpec& inc = io::findOption(io::meshOptions(), "increments").spec;
    increments_->setRange(static_cast<int>(inc.lower), static_cast<int>(inc.upper));
    increments_->setKeyboardTracking(false);
    increments_->setToolTip(tr("mesh.increments: %1. Undoable.").arg(QString::fromStdString(inc.description)));
    form->addRow(tr("&Increments"), increments_);
    gridLayout->addLayout(form);
    run_ = new QPushButton(tr("Preview Mesh"), grid);
    run_->setObjectName(QStringLiteral("meshPreviewButton"));
    run_->setToolTip(
        tr("Generate the grid, move it to the deformed geometry and check its cells (Ctrl+M)"));
    gridLayout->addWidget(run_);
    status_ = new QLabel(tr("No preview yet."), grid);
    status_->setObjectName(QStringLiteral("meshStatus"));
    status_->setWordWrap(true);
    status_->setTextFormat(Qt::PlainText);
    status_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    // Word-wrapped labels get no height for their lines inside a scroll area: reserve it.
    status_->setMinimumHeight(4 * status_->fontMetrics().lineSpacing() + 4);
    status_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    gridLayout->addWidget(status_);
    layout->addWidget(grid);

    // Quality: metric, summary, histogram, slice.
    quality_ = new QGroupBox(tr("Quality"), this);
    auto* qualityLayout = new QVBoxLayout(quality_);
    auto* metricForm = new QFormLayout;
    metric_ = new QComboBox(quality_);
    metric_->setObjectName(QStringLiteral("meshMetric"));
    for (int m = 0; m < kQualityMetrics; ++m)
        metric_->addItem(tr(metricLabel(static_cast<QualityMetric>(m))), m);
    metric_->setItemData(
        0, tr("min over the corners of det of the unit edge vectors: 1 for a box, <= 0 inverted"),
        Qt::ToolTipRole);
    metric_->setItemData(
        1, tr("min over the corners of det[e_i, e_j, e_k] (length^3): <= 0 is an inverted cell"),
        Qt::ToolTipRole);
    metric_->setItemData(
        2, tr("1 - max |cos| of the corner angles: 1 when all edges meet at right angles"),
        Qt::ToolTipRole);
    metric_->setItemData(3, tr("longest / shortest mean edge length: 1 for a cube"),
                         Qt::ToolTipRole);
    metric_->setItemData(
        4, tr("max |cos| between the cell's principal axes: 0 when they are orthogonal"),
        Qt::ToolTipRole);
    metricForm->addRow(tr("&Colour by"), metric_);
    qualityLayout->addLayout(metricForm);
    summary_ = new QLabel(quality_);
    summary_->setObjectName(QStringLiteral("meshSummary"));
    summary_->setWordWrap(true);
    summary_->setTextFormat(Qt::RichText);
    summary_->setMinimumHeight(8 * summary_->fontMetrics().lineSpacing() + 8);  // table, Jacobian, wall bend
    summary_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
    qualityLayout->addWidget(summary_);
    histogram_ = new QualityHistogram(quality_);
    qualityLayout->addWidget(histogram_);
    auto* sliceRow = new QHBoxLayout;
    auto* sliceTitle = new QLabel(tr("&Slice"), quality_);
    slice_ = new QSlider(Qt::Horizontal, quality_);
    slice_->setObjectName(QStringLiteral("meshSlice"));
    slice_->setRange(0, 0);
    slice_->setPageStep(1);
    slice_->setToolTip(
        tr("The layer of cells k = const shown by the slice (k = 0 at the wall); moving it shows "
           "the slice"));
    sliceTitle->setBuddy(slice_);
    sliceLabel_ = new QLabel(quality_);
    sliceLabel_->setMinimumWidth(
        QFontMetrics(font()).horizontalAdvance(QStringLiteral("k = 00 of 00")));
    sliceRow->addWidget(sliceTitle);
    sliceRow->addWidget(slice_, 1);
    sliceRow->addWidget(sliceLabel_);
    qualityLayout->addLayout(sliceRow);
    layout->addWidget(quality_);

    // Worst cells.
    worstBox_ = new QGroupBox(tr("Worst cells (lowest scaled Jacobian)"), this);
    auto* worstLayout = new QVBoxLayout(worstBox_);
    worst_ = new QTableWidget(0, 4, worstBox_);
    worst_->setObjectName(QStringLiteral("worstCells"));
    worst_->setHorizontalHeaderLabels(
        {tr("Block"), tr("Cell (i, j, k)"), tr("Scaled J."), QString()});
    worst_->verticalHeader()->hide();
    worst_->verticalHeader()->setDefaultSectionSize(22);
    worst_->setSelectionBehavior(QAbstractItemView::SelectRows);
    worst_->setSelectionMode(QAbstractItemView::SingleSelection);
    worst_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    worst_->setToolTip(tr("Click a cell to fly the camera to it (highlighted in yellow)"));
    worst_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
    worst_->horizontalHeader()->setStretchLastSection(true);
    worst_->setMinimumHeight(140);
    worstLayout->addWidget(worst_);
    layout->addWidget(worstBox_, 1);

    connect(run_, &QPushButton::clicked, this, [this] {
        if (running_)
            emit cancelRequested();
        else
            emit previewRequested();
    });
    connect(level_, &QComboBox::activated, this,
            [this] { emit optionsEdited(level(), increments()); });
    connect(increments_, &QSpinBox::valueChanged, this,
            [this] { emit optionsEdited(level(), increments()); });
    connect(metric_, &QComboBox::currentIndexChanged, this, [this] {
        showMetric();
        emit metricChanged(metric());
    });
    connect(slice_, &QSlider::valueChanged, this, [this](int k) {
        updateSliceLabel();
        emit sliceChanged(k);
    });
    connect(worst_, &QTableWidget::currentCellChanged, this, [this](int row) {
        if (filling_ || row < 0) return;
        lastRow_ = row;
        emit worstCellActivated(row);
    });
    connect(worst_, &QTableWidget::cellClicked, this, [this](int row) {
        if (filling_ || row != lastRow_) return;  // a new row came through currentCellChanged
        emit worstCellActivated(row);
    });
    setResult(nullptr);
}

void MeshPanel::setOptions(const QString& level, int increments) {
    const QSignalBlocker a(level_), b(increments_);
    const int i = level_->findData(level);
    level_->setCurrentIndex(i >= 0 ? i : 0);
    increments_->setValue(increments);
}

QString MeshPanel::level() const {
    return level_->currentData().toString();
}

int MeshPanel::increments() const {
    return increments_->value();
}

void MeshPanel::setRunning(bool running) {
    running_ = running;
    run_->setText(running ? tr("Cancel") : tr("Preview Mesh"));
    level_->setEnabled(!running);
    increments_->setEnabled(!running);
}

void MeshPanel::setStatus(const QString& text, bool problem) {
    status_->setText(text);
    status_->setStyleSheet(problem ? QStringLiteral("QLabel { color: #b00020; font-weight: bold; }")
                                   : QString());
}

QString MeshPanel::statusText() const {
    return status_->text();
}

void MeshPanel::setResult(std::shared_ptr<const MeshPreviewResult> result) {
    result_ = std::move(result);
    outdated_ = false;
    filling_ = true;
    worst_->setRowCount(0);  // rows of another grid: no current row to keep
    filling_ = false;
    {
        const QSignalBlocker block(slice_);
        int layers = 0;
        if (result_)
            for (const auto& g : result_->grids) layers = std::max(layers, g.dims[2] - 1);
        slice_->setRange(0, std::max(0, layers - 1));
    }
    updateSliceLabel();
    quality_->setEnabled(result_ != nullptr);
    worstBox_->setEnabled(result_ != nullptr);
    showMetric();
}

void MeshPanel::setOutdated(bool outdated) {
    outdated_ = outdated;
    quality_->setEnabled(result_ && !outdated);
    worstBox_->setEnabled(result_ && !outdated);
}

QualityMetric MeshPanel::metric() const {
    return static_cast<QualityMetric>(std::clamp(metric_->currentIndex(), 0, kQualityMetrics - 1));
}

void MeshPanel::setMetric(QualityMetric metric) {
    metric_->setCurrentIndex(static_cast<int>(metric));
}

int MeshPanel::slice() const {
    return slice_->value();
}

void MeshPanel::setSlice(int layer) {
    slice_->setValue(layer);
}

void MeshPanel::updateSliceLabel() {
    sliceLabel_->setText(result_ ? tr("k = %1 of %2").arg(slice_->value()).arg(slice_->maximum())
                                 : QString());
}

void MeshPanel::showMetric() {
    const QualityMetric m = metric();
    if (!result_) {
        summary_->setText(tr("<i>Run the preview to see the cell quality.</i>"));
        histogram_->clear();
        fillWorstCells();
        return;
    }
    const mesh::QualitySummary& qs = result_->summary;
    const mesh::MetricSummary& s = metricSummary(qs, m);
    QString text =
        QStringLiteral(
            "<table cellspacing='0' cellpadding='1'>"
            "<tr><td>%1</td><td align='right'>&nbsp;&nbsp;%2</td>"
            "<td>&nbsp;&nbsp;&nbsp;%3</td><td align='right'>&nbsp;&nbsp;%4</td></tr>"
            "<tr><td>%5</td><td align='right'>&nbsp;&nbsp;%6</td>"
            "<td>&nbsp;&nbsp;&nbsp;%7</td><td align='right'>&nbsp;&nbsp;%8</td></tr></table>")
            .arg(tr("Minimum"), number(s.min), tr("Cells"), count(qs.cellCount), tr("Maximum"),
                 number(s.max), tr("Mean"), number(s.mean));
    if (qs.nonPositiveJacobian > 0)
        text += tr("<p style='color:#b00020'><b>\u26a0 %1 with a non-positive Jacobian</b> (red in "
                   "the view): the grid "
                   "is tangled there.</p>")
                    .arg(counted(qs.nonPositiveJacobian, tr("cell"), tr("cells")));
    else
        text += tr("<p>No cell with a non-positive Jacobian (min. Jacobian %1).</p>")
                    .arg(number(qs.minJacobian.min));
    if (s.nonFinite > 0)
        text += tr("<p>%1 not finite (left out of the mean).</p>")
                    .arg(counted(s.nonFinite, tr("value"), tr("values")));
    const mesh::WallBend& bend = result_->wallBend;
    if (bend.block >= 0) {
        const QString where = tr("block %1, node (%2, %3, %4)")
                                  .arg(QString::fromStdString(bend.blockName))
                                  .arg(bend.node[0])
                                  .arg(bend.node[1])
                                  .arg(bend.node[2]);
        if (bend.degrees > study::kWallBendWarning)
            text += tr("<p style='color:#b05000'><b>\u26a0 The wall turns by %1\u00b0 from one grid node to "
                       "the next</b> (%2): a fold or a bend tighter than the grid; the flow there is not "
                       "resolved and may not converge. Smooth the shape there or refine the grid.</p>")
                        .arg(number(bend.degrees, 2), where);
        else
            text += tr("<p>Sharpest wall bend %1\u00b0 per grid node, %2.</p>").arg(number(bend.degrees, 2), where);
    }
    summary_->setText(text);

    // Bins over the view's colour range, each bar in the colour of its middle.
    const auto range = colourRange(qs, m);
    const bool logScale = useLogScale(m, range[0], range[1]);
    std::vector<long> counts =
        rangeHistogram(result_->quality, m, range[0], range[1], logScale, mesh::kQualityBins);
    std::vector<QColor> colours;
    for (std::size_t b = 0; b < counts.size(); ++b) {
        const double t = (static_cast<double>(b) + 0.5) / static_cast<double>(counts.size());
        const auto c = qualityColour(higherIsBetter(m) ? t : 1 - t);
        colours.push_back(QColor::fromRgbF(static_cast<float>(c[0]), static_cast<float>(c[1]),
                                           static_cast<float>(c[2])));
    }
    histogram_->setData(std::move(counts), std::move(colours), range[0], range[1], logScale,
                        tr(metricLabel(m)));
    fillWorstCells();
}

void MeshPanel::fillWorstCells() {
    filling_ = true;
    const QualityMetric m = metric();
    const bool extra = m != QualityMetric::ScaledJacobian;
    worst_->setColumnHidden(3, !extra);
    worst_->horizontalHeaderItem(3)->setText(extra ? tr(metricLabel(m)) : QString());
    const int keep = worst_->currentRow();
    worst_->setRowCount(0);
    if (result_) {
        const auto& worst = result_->summary.worst;
        worst_->setRowCount(static_cast<int>(worst.size()));
        for (int r = 0; r < static_cast<int>(worst.size()); ++r) {
            const mesh::CellLocation& w = worst[static_cast<std::size_t>(r)];
            auto* block = new QTableWidgetItem(QString::fromStdString(w.blockName));
            block->setToolTip(tr("Block %1 of %2").arg(w.block + 1).arg(result_->grids.size()));
            auto* cell = new QTableWidgetItem(
                QStringLiteral("(%1, %2, %3)").arg(w.cell[0]).arg(w.cell[1]).arg(w.cell[2]));
            auto* value = new QTableWidgetItem(number(w.value, 4));
            value->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
            auto* other = new QTableWidgetItem;
            other->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
            if (w.block >= 0 && w.block < static_cast<int>(result_->grids.size())) {
                const auto& g = result_->grids[static_cast<std::size_t>(w.block)];
                const auto& values =
                    metricValues(result_->quality[static_cast<std::size_t>(w.block)], m);
                other->setText(number(
                    values[static_cast<std::size_t>(g.cell(w.cell[0], w.cell[1], w.cell[2]))], 4));
            }
            const QString where = tr("centroid (%1, %2, %3)")
                                      .arg(number(w.centroid[0], 4), number(w.centroid[1], 4),
                                           number(w.centroid[2], 4));
            for (QTableWidgetItem* item : {block, cell, value, other}) {
                if (item != block) item->setToolTip(where);
                if (!(w.value > 0)) item->setForeground(QColor(0xb0, 0x00, 0x20));
            }
            worst_->setItem(r, 0, block);
            worst_->setItem(r, 1, cell);
            worst_->setItem(r, 2, value);
            worst_->setItem(r, 3, other);
        }
        if (keep >= 0 && keep < worst_->rowCount()) worst_->setCurrentCell(keep, 0);
    }
    lastRow_ = worst_->currentRow();
    filling_ = false;
}

}  // namespace aero::ui
