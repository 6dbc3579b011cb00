#pragma once
// A small bar chart of a cell-quality histogram (ui::rangeHistogram), drawn with
// QPainter: bar heights on a log scale (a few bad cells stay visible next to thousands of good
// ones), each bar in the colour its values have in the 3D view, the count above it, the range
// below. Hovering a bar shows its interval and count. GUI thread only; no VTK.
#include <QColor>
#include <QString>
#include <QWidget>
#include <vector>

namespace aero::ui {

class QualityHistogram : public QWidget {
    Q_OBJECT

  public:
    explicit QualityHistogram(QWidget* parent = nullptr);

    /// Bins of equal width over [lo, hi] (in log10 where `logScale`); one colour per bin.
    /// `caption` names the metric.
    void setData(std::vector<long> counts, std::vector<QColor> colours, double lo, double hi,
                 bool logScale, const QString& caption);
    void clear();
    const std::vector<long>& counts() const { return counts_; }

    QSize sizeHint() const override { return {280, 115}; }
    QSize minimumSizeHint() const override { return {160, 95}; }

  protected:
    void paintEvent(QPaintEvent* e) override;
    bool event(QEvent* e) override;

  private:
    QRectF plotArea() const;
    int binAt(const QPointF& pos) const;

    std::vector<long> counts_;
    std::vector<QColor> colours_;
    double edge(int i) const;  // lower edge of bin i (i = bins: the upper end)

    double lo_ = 0, hi_ = 1;
    bool log_ = false;
    QString caption_;
};

}  // namespace aero::ui
