#pragma once
// A 2D line plot for the application's live and result plots (the flow's residual history, Cp
// along spanwise cuts, airfoil sections; later the optimizer's objective and optimality):
//   axes       linear or log10, each with a label and unit, automatic or fixed range, ticks at
//              1-2-5 steps or decades, optionally equal scales (shapes keep their proportions)
//              and a reversed y (Cp grows downwards, the aerodynamicist's convention);
//   series     polylines with optional markers (a NaN y breaks the line), drawn in order;
//   bands      shaded x intervals with a label (e.g. the phases of a solve);
//   hover      the point nearest the mouse is ringed and its series, x and y shown in a box;
//   export     PNG (the widget's picture at any scale), SVG (written from the same drawing
//              primitives: no Qt SVG module needed) and CSV (the data), from the context menu too.
// The plot is drawn from a list of primitives built for a given size, so the screen and the
// SVG file show the same picture. GUI thread only; no VTK.
#include <QColor>
#include <QPointF>
#include <QString>
#include <QWidget>
#include <functional>
#include <optional>
#include <vector>

namespace aero::ui {

struct PlotAxis {
    QString label;        // "Iteration", "Relative residual"
    QString unit;         // shown as "label [unit]" when not empty
    bool log = false;     // log10 scale (non-positive values are not drawn)
    bool reversed = false;  // values grow downwards (y) or to the left (x)
    std::optional<std::pair<double, double>> range;  // fixed range; automatic when unset
    double minimumSpan = 0;  // automatic ranges are at least this wide (linear axes)
};

enum class MarkerShape { None, Circle, Square, Diamond, Cross };

struct PlotSeries {
    QString name;
    QColor colour = QColor(40, 90, 170);
    double lineWidth = 1.6;   // 0: no line
    Qt::PenStyle lineStyle = Qt::SolidLine;
    MarkerShape marker = MarkerShape::None;
    double markerSize = 5;    // pixels
    bool legend = true;       // listed in the legend
    std::vector<QPointF> points;  // (x, y); a NaN y ends a polyline piece
};

struct PlotBand {
    double x0 = 0, x1 = 0;
    QColor colour = QColor(230, 236, 248);
    QString label;  // written at the band's top
};

class PlotWidget : public QWidget {
    Q_OBJECT

  public:
    explicit PlotWidget(QWidget* parent = nullptr);

    void setTitle(const QString& title);
    QString title() const { return title_; }
    PlotAxis& xAxis() { return x_; }
    PlotAxis& yAxis() { return y_; }
    const PlotAxis& xAxis() const { return x_; }
    const PlotAxis& yAxis() const { return y_; }
    /// Equal length per pixel on both axes (profiles, planforms).
    void setEqualAspect(bool on);
    /// Shown in the middle when there is no data.
    void setPlaceholder(const QString& text);

    /// Series are addressed by index (addSeries returns it).
    int addSeries(PlotSeries series);
    PlotSeries& series(int index) { return series_[static_cast<std::size_t>(index)]; }
    const std::vector<PlotSeries>& allSeries() const { return series_; }
    void appendPoint(int series, QPointF p);
    void clearSeries();  // removes all series and bands
    void setBands(std::vector<PlotBand> bands);
    const std::vector<PlotBand>& bands() const { return bands_; }
    /// Call after changing series()/axes in place.
    void changed();

    /// The drawn ranges (after automatic ranging and equal aspect), in data units.
    std::pair<double, double> xRange() const;
    std::pair<double, double> yRange() const;
    /// Widget position of a data point (for tests and tools); NaN if not drawable.
    QPointF toWidget(QPointF data) const;
    /// The hovered point's text ("series\nx: ..., y: ..."), empty when none.
    QString hoverText() const { return hoverText_; }
    /// Hovers the point nearest to widget position `pos` (what a mouse move does).
    void hoverAt(QPointF pos);

    /// The picture at `scale` times the widget's size.
    QImage toImage(double scale = 2.0) const;
    bool exportPng(const QString& path, double scale = 2.0) const;
    /// An SVG document of the picture at the widget's size.
    QString toSvg() const;
    bool exportSvg(const QString& path) const;
    /// Long format: one line per point, "series,x,y" under a header naming the axes; or what
    /// setCsvWriter's function returns.
    QString toCsv() const;
    bool exportCsv(const QString& path) const;
    void setCsvWriter(std::function<QString()> writer) { csvWriter_ = std::move(writer); }
    /// Asks for a file and exports by its suffix (.png, .svg, .csv).
    void exportWithDialog();

    QSize sizeHint() const override { return {420, 260}; }
    QSize minimumSizeHint() const override { return {220, 140}; }

  protected:
    void paintEvent(QPaintEvent* e) override;
    void mouseMoveEvent(QMouseEvent* e) override;
    void leaveEvent(QEvent* e) override;
    void contextMenuEvent(QContextMenuEvent* e) override;
    void resizeEvent(QResizeEvent* e) override;

  public:
    /// One drawing primitive (the display list shared by paintEvent and toSvg).
    struct Primitive {
        enum Kind { Polyline, Rect, Text, Marker } kind = Polyline;
        std::vector<QPointF> points;  // Polyline; Marker: its centre (one point)
        QRectF rect;                  // Rect; Text: the box the text is aligned in
        QColor stroke, fill;          // invalid: none
        double width = 1;
        Qt::PenStyle style = Qt::SolidLine;
        QString text;
        int align = 0;                // Qt::Alignment of Text
        double fontPx = 11;
        bool bold = false;
        bool vertical = false;        // Text rotated by -90 degrees about the rect's centre
        MarkerShape shape = MarkerShape::Circle;
        double size = 5;
    };
    /// The primitives of the picture at `size` (widget pixels).
    std::vector<Primitive> primitives(QSizeF size) const;

  private:
    struct Frame;  // plot area and ranges for one size
    Frame frame(QSizeF size) const;
    void rebuildHover();

    QString title_, placeholder_;
    PlotAxis x_, y_;
    bool equalAspect_ = false;
    std::vector<PlotSeries> series_;
    std::vector<PlotBand> bands_;
    std::function<QString()> csvWriter_;
    QPointF mouse_{-1, -1};
    int hoverSeries_ = -1, hoverPoint_ = -1;
    QString hoverText_;
};

/// "1.5e-03" style numbers for tick labels and hover boxes: `digits` significant digits,
/// plain notation between 1e-3 and 1e5.
QString plotNumber(double v, int digits = 4);

}  // namespace aero::ui
