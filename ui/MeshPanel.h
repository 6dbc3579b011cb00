#pragma once
// The "Mesh Quality" panel of the mesh preview:
//   Grid       the case's mesh level (coarse / medium / paper) and elasticity increments
//              (edits of the case, undoable), the Preview / Cancel button and a status line;
//   Quality    the metric that colours the view, its min / mean / max, the count of cells with
//              a non-positive Jacobian, a histogram, and the slider of the constant-k slice;
//   Worst      the cells with the lowest scaled Jacobian (block, cell, values); choosing a row
//              asks to fly the camera there.
// The panel only shows and asks: MeshPreviewer runs the job and drives the scene. GUI thread
// only; no VTK.
#include <QString>
#include <QWidget>
#include <memory>

#include "MeshPreview.h"

class QComboBox;
class QGroupBox;
class QLabel;
class QPushButton;
class QSlider;
class QSpinBox;
class QTableWidget;

namespace aero::ui {

class QualityHistogram;

class MeshPanel : public QWidget {
    Q_OBJECT

  public:
    explicit MeshPanel(QWidget* parent = nullptr);

    /// Shows the case's options (no signal).
    void setOptions(const QString& level, int increments);
    QString level() const;
    int increments() const;

    /// While running, the button reads Cancel and the options are locked.
    void setRunning(bool running);
    bool running() const { return running_; }
    void setStatus(const QString& text, bool problem = false);
    QString statusText() const;

    /// The preview to describe (null: none). The panel keeps it for metric changes.
    void setResult(std::shared_ptr<const MeshPreviewResult> result);
    /// Greys the quality part out (the view no longer shows this grid).
    void setOutdated(bool outdated);
    bool outdated() const { return outdated_; }

    QualityMetric metric() const;
    void setMetric(QualityMetric metric);
    int slice() const;
    void setSlice(int layer);

    QTableWidget* worstCellTable() const { return worst_; }
    QualityHistogram* histogram() const { return histogram_; }
    QPushButton* previewButton() const { return run_; }
    QComboBox* levelBox() const { return level_; }
    QSpinBox* incrementsBox() const { return increments_; }
    QComboBox* metricBox() const { return metric_; }
    QSlider* sliceSlider() const { return slice_; }
    QLabel* summaryLabel() const { return summary_; }

  signals:
    void previewRequested();
    void cancelRequested();
    /// The user changed the level or the increments.
    void optionsEdited(const QString& level, int increments);
    void metricChanged(QualityMetric metric);
    void sliceChanged(int layer);
    /// Row `index` of the worst cells (MeshPreviewResult::summary.worst[index]) was chosen.
    void worstCellActivated(int index);

  private:
    void showMetric();
    void fillWorstCells();
    void updateSliceLabel();

    std::shared_ptr<const MeshPreviewResult> result_;
    bool running_ = false;
    bool outdated_ = false;
    bool filling_ = false;
    int lastRow_ = -1;
    QComboBox* level_ = nullptr;
    QSpinBox* increments_ = nullptr;
    QPushButton* run_ = nullptr;
    QLabel* status_ = nullptr;
    QGroupBox* quality_ = nullptr;
    QComboBox* metric_ = nullptr;
    QLabel* summary_ = nullptr;
    QualityHistogram* histogram_ = nullptr;
    QSlider* slice_ = nullptr;
    QLabel* sliceLabel_ = nullptr;
    QGroupBox* worstBox_ = nullptr;
    QTableWidget* worst_ = nullptr;
};

}  // namespace aero::ui
