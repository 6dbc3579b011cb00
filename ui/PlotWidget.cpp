#include "PlotWidget.h"

#include <QContextMenuEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QFontMetricsF>
#include <QImage>
#include <QMenu>
#include <QMessageBox>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QRegularExpression>
#include <QSaveFile>
#include <QTextStream>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "Resources.h"

namespace aero::ui {

namespace {

constexpr double kTickFont = 10.5;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kLabelFont = 11.5;
constexpr double kTitleFont = 12.5;
constexpr double kHoverRadius = 12;  // pixels
const QColor kText(40, 42, 48);
const QColor kGrid(222, 225, 232);
const QColor kFrame(120, 124, 134);

QFont fontPx(double px, bool bold = false) {
    QFont f;
    f.setPixelSize(std::max(1, static_cast<int>(std::lround(px))));
    f.setBold(bold);
    return f;
}

double textWidth(const QString& s, double px, bool bold = false) {
    return QFontMetricsF(fontPx(px, bold)).horizontalAdvance(s);
}

// `s` shortened with an ellipsis to at most `width` pixels (a small plot keeps its text inside).
QString elided(const QString& s, double px, double width, bool bold = false) {
    return QFontMetricsF(fontPx(px, bold)).elidedText(s, Qt::ElideRight, std::max(0.0, width));
}

QString axisTitle(const PlotAxis& a) {
    return a.unit.isEmpty() ? a.label : QStringLiteral("%1 [%2]").arg(a.label, a.unit);
}

QString superscript(int e) {
    static const QString digits = QStringLiteral("\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079");
    QString s = e < 0 ? QStringLiteral("\u207b") : QString();
    const QString n = QString::number(std::abs(e));
    for (QChar c : n) s += digits[c.digitValue()];
    return s;
}

struct Tick {
    double at;  // in axis space (log10 for log axes)
    QString label;
};

// Ticks of [lo, hi] in axis space.
std::vector<Tick> ticks(const PlotAxis& a, double lo, double hi) {
    std::vector<Tick> out;
    if (!(hi > lo)) return out;
    if (a.log) {
        if (hi - lo >= 1.0) {
            const int first = static_cast<int>(std::ceil(lo - 1e-9)), last = static_cast<int>(std::floor(hi + 1e-9));
            const int stride = std::max(1, static_cast<int>(std::ceil((last - first + 1) / 8.0)));
            for (int e = first; e <= last; ++e)
                if ((e - first) % stride == 0) out.push_back({double(e), QStringLiteral("10") + superscript(e)});
            return out;
        }
        // Less than a decade: 1, 2, 5 times powers of ten.
        for (int e = static_cast<int>(std::floor(lo)) - 1; e <= static_cast<int>(std::ceil(hi)); ++e)
            for (double m : {1.0, 2.0, 5.0}) {
                const double v = m * std::pow(10.0, e), t = std::log10(v);
                if (t >= lo - 1e-12 && t <= hi + 1e-12) out.push_back({t, plotNumber(v, 3)});
            }
        if (out.size() >= 2) return out;
        out.clear();
        const double vlo = std::pow(10.0, lo), vhi = std::pow(10.0, hi);
        PlotAxis linear = a;
        linear.log = false;
        for (const Tick& t : ticks(linear, vlo, vhi)) out.push_back({std::log10(t.at), t.label});
        return out;
    }
    const double raw = (hi - lo) / 6.0;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * mag >= raw) {
            step = m * mag;
            break;
        }
    for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) {
        const double clean = std::abs(v) < 1e-9 * step ? 0.0 : v;
        out.push_back({clean, plotNumber(clean, 4)});
    }
    return out;
}

QString svgColour(const QColor& c) {
    return c.isValid() ? c.name(QColor::HexRgb) : QStringLiteral("none");
}

QString svgEscape(QString s) {
    s.replace(QLatin1Char('&'), QStringLiteral("&amp;"));
    s.replace(QLatin1Char('<'), QStringLiteral("&lt;"));
    s.replace(QLatin1Char('>'), QStringLiteral("&gt;"));
    return s;
}

QString svgNum(double v) {
    return QString::number(v, 'f', 2);
}

QString dashArray(Qt::PenStyle s, double w) {
    switch (s) {
        case Qt::DashLine:
            return QStringLiteral("%1,%2").arg(svgNum(4 * w), svgNum(2.5 * w));
        case Qt::DotLine:
            return QStringLiteral("%1,%2").arg(svgNum(w), svgNum(2 * w));
        default:
            return {};
    }
}

QPainterPath markerPath(MarkerShape shape, QPointF c, double size) {
    QPainterPath path;
    const double r = size / 2;
    switch (shape) {
        case MarkerShape::Circle:
            path.addEllipse(c, r, r);
            break;
        case MarkerShape::Square:
            path.addRect(QRectF(c.x() - r, c.y() - r, size, size));
            break;
        case MarkerShape::Diamond:
            path.moveTo(c.x(), c.y() - r * 1.3);
            path.lineTo(c.x() + r * 1.3, c.y());
            path.lineTo(c.x(), c.y() + r * 1.3);
            path.lineTo(c.x() - r * 1.3, c.y());
            path.closeSubpath();
            break;
        case MarkerShape::Cross:
            path.moveTo(c.x() - r, c.y() - r);
            path.lineTo(c.x() + r, c.y() + r);
            path.moveTo(c.x() - r, c.y() + r);
            path.lineTo(c.x() + r, c.y() - r);
            break;
        case MarkerShape::None:
            break;
    }
    return path;
}

bool saveText(const QString& path, const QString& text) {
    QSaveFile f(path);
    if (!f.open(QIODevice::WriteOnly | QIODevice::Text)) return false;
    const QByteArray bytes = text.toUtf8();
    if (f.write(bytes) != bytes.size()) return false;
    return f.commit();
}

}  // namespace

QString plotNumber(double v, int digits) {
    if (std::isnan(v)) return QStringLiteral("NaN");
    if (std::isinf(v)) return v > 0 ? QStringLiteral("\u221e") : QStringLiteral("\u2212\u221e");
    const double a = std::abs(v);
    if (a == 0) return QStringLiteral("0");
    if (a >= 1e-3 && a < 1e5) return QString::number(v, 'g', digits);
    return QString::number(v, 'e', std::max(0, digits - 2));
}

// ---- Frame: the plot area and the ranges for one size --------------------------------------------

struct PlotWidget::Frame {
    QRectF area;                 // the plot area (inside the axes)
    double xlo = 0, xhi = 1;     // axis space (log10 for log axes)
    double ylo = 0, yhi = 1;
    std::vector<Tick> xticks, yticks;
    bool empty = true;

    double tx(const PlotAxis& a, double v) const { return a.log ? (v > 0 ? std::log10(v) : std::nan("")) : v; }
    QPointF map(const PlotAxis& ax, const PlotAxis& ay, QPointF p) const {
        const double x = tx(ax, p.x()), y = tx(ay, p.y());
        if (!std::isfinite(x) || !std::isfinite(y)) return {std::nan(""), std::nan("")};
        double u = (x - xlo) / (xhi - xlo), w = (y - ylo) / (yhi - ylo);
        if (ax.reversed) u = 1 - u;
        if (ay.reversed) w = 1 - w;
        return {area.left() + u * area.width(), area.bottom() - w * area.height()};
    }
};

PlotWidget::Frame PlotWidget::frame(QSizeF size) const {
    Frame f;
    auto range = [&](const PlotAxis& a, bool isX, double& lo, double& hi) {
        if (a.range) {
            lo = f.tx(a, a.range->first);
            hi = f.tx(a, a.range->second);
            if (std::isfinite(lo) && std::isfinite(hi) && hi > lo) return true;
        }
        lo = std::numeric_limits<double>::infinity();
        hi = -lo;
        for (const PlotSeries& s : series_)
            for (const QPointF& p : s.points) {
                const double t = f.tx(a, isX ? p.x() : p.y());
                if (!std::isfinite(t) || !std::isfinite(isX ? p.y() : p.x())) continue;
                lo = std::min(lo, t);
                hi = std::max(hi, t);
            }
        if (isX)
            for (const PlotBand& b : bands_)
                for (double v : {b.x0, b.x1}) {
                    const double t = f.tx(a, v);
                    if (std::isfinite(t)) {
                        lo = std::min(lo, t);
                        hi = std::max(hi, t);
                    }
                }
        if (!(lo <= hi)) {
            lo = a.log ? -1 : 0;
            hi = 1;
            return false;
        }
        if (a.log) {
            lo = std::floor(lo + 1e-9);
            hi = std::ceil(hi - 1e-9);
            if (hi <= lo) hi = lo + 1;
        } else {
            if (hi - lo < a.minimumSpan) {
                const double c = 0.5 * (lo + hi);
                lo = c - 0.5 * a.minimumSpan;
                hi = c + 0.5 * a.minimumSpan;
            }
            if (!(hi > lo)) {
                const double pad = std::max(1e-12, 0.1 * std::abs(lo));
                lo -= pad;
                hi += pad;
            }
            const double pad = 0.04 * (hi - lo);
            lo -= pad;
            hi += pad;
        }
        return true;
    };
    const bool hasX = range(x_, true, f.xlo, f.xhi);
    const bool hasY = range(y_, false, f.ylo, f.yhi);
    f.empty = !(hasX && hasY);
    f.yticks = ticks(y_, f.ylo, f.yhi);

    // Margins from the labels' sizes.
    double yLabelWidth = 0;
    for (const Tick& t : f.yticks) yLabelWidth = std::max(yLabelWidth, textWidth(t.label, kTickFont));
    const double top = (title_.isEmpty() ? 10.0 : kTitleFont * 1.9);
    const double left = 10 + (y_.label.isEmpty() ? 0.0 : kLabelFont * 1.6) + yLabelWidth + 6;
    const double bottom = 8 + kTickFont * 1.5 + (x_.label.isEmpty() ? 0.0 : kLabelFont * 1.7);
    const double right = 14;
    f.area = QRectF(left, top, std::max(10.0, size.width() - left - right), std::max(10.0, size.height() - top - bottom));

    if (equalAspect_ && !x_.log && !y_.log && !f.empty) {
        const double ux = (f.xhi - f.xlo) / f.area.width(), uy = (f.yhi - f.ylo) / f.area.height();
        if (ux > uy) {
            const double c = 0.5 * (f.ylo + f.yhi), h = 0.5 * ux * f.area.height();
            f.ylo = c - h;
            f.yhi = c + h;
        } else {
            const double c = 0.5 * (f.xlo + f.xhi), h = 0.5 * uy * f.area.width();
            f.xlo = c - h;
            f.xhi = c + h;
        }
        f.yticks = ticks(y_, f.ylo, f.yhi);
    }
    f.xticks = ticks(x_, f.xlo, f.xhi);
    // Thin out x labels that would overlap.
    if (f.xticks.size() > 2) {
        double widest = 0;
        for (const Tick& t : f.xticks) widest = std::max(widest, textWidth(t.label, kTickFont));
        const double spacing = f.area.width() / static_cast<double>(f.xticks.size());
        const int stride = spacing > 0 ? static_cast<int>(std::ceil((widest + 8) / spacing)) : 1;
        if (stride > 1) {
            std::vector<Tick> kept;
            for (std::size_t i = 0; i < f.xticks.size(); i += static_cast<std::size_t>(stride)) kept.push_back(f.xticks[i]);
            f.xticks = kept;
        }
    }
    return f;
}

// ---- Widget ---------------------------------------------------------------------------------------

PlotWidget::PlotWidget(QWidget* parent) : QWidget(parent) {
    setMouseTracking(true);
    setAttribute(Qt::WA_OpaquePaintEvent);
    setContextMenuPolicy(Qt::DefaultContextMenu);
    setToolTip(tr("Right-click to export the plot (PNG, SVG) or its data (CSV)"));
}

void PlotWidget::setTitle(const QString& title) {
    title_ = title;
    update();
}

void PlotWidget::setEqualAspect(bool on) {
    equalAspect_ = on;
    update();
}

void PlotWidget::setPlaceholder(const QString& text) {
    placeholder_ = text;
    update();
}

int PlotWidget::addSeries(PlotSeries series) {
    series_.push_back(std::move(series));
    changed();
    return static_cast<int>(series_.size()) - 1;
}

void PlotWidget::appendPoint(int series, QPointF p) {
    if (series < 0 || series >= static_cast<int>(series_.size())) return;
    series_[static_cast<std::size_t>(series)].points.push_back(p);
    update();
}

void PlotWidget::clearSeries() {
    series_.clear();
    bands_.clear();
    changed();
}

void PlotWidget::setBands(std::vector<PlotBand> bands) {
    bands_ = std::move(bands);
    update();
}

void PlotWidget::changed() {
    rebuildHover();
    update();
}

std::pair<double, double> PlotWidget::xRange() const {
    const Frame f = frame(size());
    return x_.log ? std::pair{std::pow(10.0, f.xlo), std::pow(10.0, f.xhi)} : std::pair{f.xlo, f.xhi};
}

std::pair<double, double> PlotWidget::yRange() const {
    const Frame f = frame(size());
    return y_.log ? std::pair{std::pow(10.0, f.ylo), std::pow(10.0, f.yhi)} : std::pair{f.ylo, f.yhi};
}

QPointF PlotWidget::toWidget(QPointF data) const {
    return frame(size()).map(x_, y_, data);
}

void PlotWidget::hoverAt(QPointF pos) {
    mouse_ = pos;
    rebuildHover();
    update();
}

void PlotWidget::rebuildHover() {
    hoverSeries_ = hoverPoint_ = -1;
    hoverText_.clear();
    if (mouse_.x() < 0) return;
    const Frame f = frame(size());
    double best = kHoverRadius;
    for (std::size_t s = 0; s < series_.size(); ++s) {
        const auto& pts = series_[s].points;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const QPointF w = f.map(x_, y_, pts[i]);
            if (!std::isfinite(w.x()) || !std::isfinite(w.y())) continue;
            const double d = std::hypot(w.x() - mouse_.x(), w.y() - mouse_.y());
            if (d < best) {
                best = d;
                hoverSeries_ = static_cast<int>(s);
                hoverPoint_ = static_cast<int>(i);
            }
        }
    }
    if (hoverSeries_ < 0) return;
    const QPointF p = series_[static_cast<std::size_t>(hoverSeries_)].points[static_cast<std::size_t>(hoverPoint_)];
    auto name = [](const PlotAxis& a, const char* fallback) {
        return a.label.isEmpty() ? QString::fromLatin1(fallback) : a.label;
    };
    hoverText_ = QStringLiteral("%1\n%2: %3\n%4: %5")
                     .arg(series_[static_cast<std::size_t>(hoverSeries_)].name, name(x_, "x"), plotNumber(p.x(), 6),
                          name(y_, "y"), plotNumber(p.y(), 6));
}

void PlotWidget::mouseMoveEvent(QMouseEvent* e) {
    hoverAt(e->position());
}

void PlotWidget::leaveEvent(QEvent*) {
    mouse_ = {-1, -1};
    rebuildHover();
    update();
}

void PlotWidget::resizeEvent(QResizeEvent*) {
    rebuildHover();
}

void PlotWidget::contextMenuEvent(QContextMenuEvent* e) {
    QMenu menu(this);
    menu.addAction(tr("Export Plot or Data..."), this, &PlotWidget::exportWithDialog);
    menu.exec(e->globalPos());
}

// ---- Primitives -----------------------------------------------------------------------------------

std::vector<PlotWidget::Primitive> PlotWidget::primitives(QSizeF size) const {
    std::vector<Primitive> out;
    const Frame f = frame(size);
    auto rect = [&](QRectF r, QColor fill, QColor stroke = {}, double width = 1) {
        Primitive p;
        p.kind = Primitive::Rect;
        p.rect = r;
        p.fill = fill;
        p.stroke = stroke;
        p.width = width;
        out.push_back(p);
    };
    auto line = [&](std::vector<QPointF> pts, QColor c, double width, Qt::PenStyle style = Qt::SolidLine) {
        Primitive p;
        p.kind = Primitive::Polyline;
        p.points = std::move(pts);
        p.stroke = c;
        p.width = width;
        p.style = style;
        out.push_back(std::move(p));
    };
    auto text = [&](QPointF at, const QString& s, int align, double px, bool bold = false, bool vertical = false,
                    QColor c = kText) {
        Primitive p;
        p.kind = Primitive::Text;
        p.points = {at};
        p.text = s;
        p.align = align;
        p.fontPx = px;
        p.bold = bold;
        p.vertical = vertical;
        p.fill = c;
        out.push_back(p);
    };
    auto marker = [&](QPointF at, MarkerShape shape, double px, QColor c, QColor fill) {
        Primitive p;
        p.kind = Primitive::Marker;
        p.points = {at};
        p.shape = shape;
        p.size = px;
        p.stroke = c;
        p.fill = fill;
        out.push_back(p);
    };

    rect(QRectF(QPointF(0, 0), size), Qt::white);
    const QRectF& a = f.area;
    if (!title_.isEmpty())
        text({size.width() / 2, kTitleFont * 1.3},
             elided(title_, kTitleFont, size.width() - 8, true), Qt::AlignHCenter, kTitleFont,
             true);

    // Bands behind everything.
    for (const PlotBand& b : bands_) {
        const QPointF p0 = f.map(x_, y_, {b.x0, y_.log ? std::pow(10.0, f.ylo) : f.ylo});
        const QPointF p1 = f.map(x_, y_, {b.x1, y_.log ? std::pow(10.0, f.ylo) : f.ylo});
        if (!std::isfinite(p0.x()) || !std::isfinite(p1.x())) continue;
        const double l = std::clamp(std::min(p0.x(), p1.x()), a.left(), a.right());
        const double r = std::clamp(std::max(p0.x(), p1.x()), a.left(), a.right());
        if (r - l < 0.5) continue;
        rect(QRectF(l, a.top(), r - l, a.height()), b.colour);
        if (!b.label.isEmpty() && r - l > textWidth(b.label, kTickFont) + 6)
            text({0.5 * (l + r), a.top() + kTickFont + 3}, b.label, Qt::AlignHCenter, kTickFont, false, false,
                 QColor(90, 96, 110));
    }

    // Grid lines and tick labels.
    const double xValueLo = x_.log ? std::pow(10.0, f.xlo) : f.xlo;
    const double yValueLo = y_.log ? std::pow(10.0, f.ylo) : f.ylo;
    for (const Tick& t : f.xticks) {
        const QPointF p = f.map(x_, y_, {x_.log ? std::pow(10.0, t.at) : t.at, yValueLo});
        if (!std::isfinite(p.x())) continue;
        line({{p.x(), a.top()}, {p.x(), a.bottom()}}, kGrid, 1);
        text({p.x(), a.bottom() + kTickFont + 5}, t.label, Qt::AlignHCenter, kTickFont);
    }
    for (const Tick& t : f.yticks) {
        const QPointF p = f.map(x_, y_, {xValueLo, y_.log ? std::pow(10.0, t.at) : t.at});
        if (!std::isfinite(p.y())) continue;
        line({{a.left(), p.y()}, {a.right(), p.y()}}, kGrid, 1);
        text({a.left() - 5, p.y() + 0.35 * kTickFont}, t.label, Qt::AlignRight, kTickFont);
    }
    rect(a, {}, kFrame, 1);
    if (!x_.label.isEmpty())
        text({a.center().x(), size.height() - 8},
             elided(axisTitle(x_), kLabelFont,
                    2 * std::min(a.center().x(), size.width() - a.center().x()) - 8),
             Qt::AlignHCenter, kLabelFont);
    if (!y_.label.isEmpty())
        text({8 + kLabelFont, a.center().y()}, elided(axisTitle(y_), kLabelFont, a.height() + 10),
             Qt::AlignHCenter, kLabelFont, false, true);

    if (f.empty && !placeholder_.isEmpty())
        text(a.center() + QPointF(0, 0.35 * kLabelFont),
             elided(placeholder_, kLabelFont, a.width() - 8), Qt::AlignHCenter, kLabelFont, false,
             false, QColor(130, 134, 144));

    // Series: polylines kept inside the plot area, then markers.
    auto inside = [&](QPointF p) { return a.adjusted(-1, -1, 1, 1).contains(p); };
    for (const PlotSeries& s : series_) {
        if (s.lineWidth > 0) {
            std::vector<QPointF> piece;
            auto flush = [&] {
                if (piece.size() >= 2) line(piece, s.colour, s.lineWidth, s.lineStyle);
                piece.clear();
            };
            for (const QPointF& p : s.points) {
                const QPointF w = f.map(x_, y_, p);
                if (!std::isfinite(w.x()) || !std::isfinite(w.y())) {
                    flush();
                    continue;
                }
                // Clamp to the area (a fixed range may cut the data); lines leaving it are
                // flattened on the frame rather than drawn over the labels.
                piece.push_back({std::clamp(w.x(), a.left(), a.right()), std::clamp(w.y(), a.top(), a.bottom())});
            }
            flush();
        }
        if (s.marker != MarkerShape::None)
            for (const QPointF& p : s.points) {
                const QPointF w = f.map(x_, y_, p);
                if (std::isfinite(w.x()) && std::isfinite(w.y()) && inside(w))
                    marker(w, s.marker, s.markerSize, s.colour, s.marker == MarkerShape::Cross ? QColor() : s.colour);
            }
    }

    // Legend (inside, in the corner where it hides the least of the data; top right on a tie).
    // In a plot too small for it (it would hide data and cover a third of the area) it is left
    // out: hovering names the series.
    std::vector<const PlotSeries*> listed;
    for (const PlotSeries& s : series_)
        if (s.legend && !s.name.isEmpty()) listed.push_back(&s);
    QRectF legendBox;
    if (!listed.empty()) {
        double w = 0;
        for (const PlotSeries* s : listed) w = std::max(w, textWidth(s->name, kTickFont));
        const double rowH = kTickFont * 1.5, boxW = w + 38, boxH = rowH * static_cast<double>(listed.size()) + 6;
        const std::array<QRectF, 4> corners = {
            QRectF(a.right() - boxW - 6, a.top() + 6, boxW, boxH),
            QRectF(a.left() + 6, a.top() + 6, boxW, boxH),
            QRectF(a.right() - boxW - 6, a.bottom() - boxH - 6, boxW, boxH),
            QRectF(a.left() + 6, a.bottom() - boxH - 6, boxW, boxH)};
        std::array<int, 4> hidden{};
        for (const PlotSeries& s : series_) {
            QPointF previous(kNaN, kNaN);
            for (const QPointF& p : s.points) {
                const QPointF q = f.map(x_, y_, p);
                if (!std::isfinite(q.x()) || !std::isfinite(q.y())) {
                    previous = QPointF(kNaN, kNaN);
                    continue;
                }
                // The point and a few along the segment to it (a line crossing the box counts).
                const int steps = std::isfinite(previous.x()) ? 8 : 1;
                for (int k = 0; k < steps; ++k) {
                    const double t = steps == 1 ? 1.0 : static_cast<double>(k + 1) / steps;
                    const QPointF at =
                        std::isfinite(previous.x()) ? previous + t * (q - previous) : q;
                    for (std::size_t c = 0; c < corners.size(); ++c)
                        hidden[c] += corners[c].contains(at) ? 1 : 0;
                }
                previous = q;
            }
        }
        const auto best = std::min_element(hidden.begin(), hidden.end());
        legendBox = corners[static_cast<std::size_t>(best - hidden.begin())];
        if ((*best > 0 && boxW * boxH > a.width() * a.height() / 3) || boxW > a.width() - 12 ||
            boxH > a.height() - 12)
            listed.clear();
    }
    if (!listed.empty()) {
        const double rowH = kTickFont * 1.5;
        rect(legendBox, QColor(255, 255, 255, 235), QColor(200, 203, 210), 1);
        for (std::size_t i = 0; i < listed.size(); ++i) {
            const PlotSeries& s = *listed[i];
            const double y = legendBox.top() + 3 + rowH * (static_cast<double>(i) + 0.5);
            if (s.lineWidth > 0)
                line({{legendBox.left() + 6, y}, {legendBox.left() + 26, y}}, s.colour, s.lineWidth,
                     s.lineStyle);
            if (s.marker != MarkerShape::None)
                marker({legendBox.left() + 16, y}, s.marker, s.markerSize, s.colour,
                       s.marker == MarkerShape::Cross ? QColor() : s.colour);
            text({legendBox.left() + 32, y + 0.35 * kTickFont}, s.name, Qt::AlignLeft, kTickFont);
        }
    }

    // Hover: ring and box.
    if (hoverSeries_ >= 0 && size == QSizeF(this->size())) {
        const PlotSeries& s = series_[static_cast<std::size_t>(hoverSeries_)];
        const QPointF w = f.map(x_, y_, s.points[static_cast<std::size_t>(hoverPoint_)]);
        marker(w, MarkerShape::Circle, 11, s.colour, {});
        const QStringList lines = hoverText_.split(QLatin1Char('\n'));
        double tw = 0;
        for (const QString& l : lines) tw = std::max(tw, textWidth(l, kTickFont));
        const double rowH = kTickFont * 1.4, bw = tw + 12, bh = rowH * lines.size() + 6;
        QRectF box(w.x() + 10, w.y() - bh - 8, bw, bh);
        if (box.right() > size.width() - 2) box.moveRight(w.x() - 10);
        if (box.top() < 2) box.moveTop(w.y() + 10);
        rect(box, QColor(255, 255, 240, 245), QColor(150, 150, 150), 1);
        for (int i = 0; i < lines.size(); ++i)
            text({box.left() + 6, box.top() + 3 + rowH * (i + 0.75)}, lines[i], Qt::AlignLeft, kTickFont, i == 0);
    }
    return out;
}

// ---- Painting ---------------------------------------------------------------------------------------

namespace {

void paintPrimitives(QPainter& p, const std::vector<PlotWidget::Primitive>& prims) {
    using Prim = PlotWidget::Primitive;
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setRenderHint(QPainter::TextAntialiasing, true);
    for (const Prim& q : prims) {
        switch (q.kind) {
            case Prim::Rect:
                p.setPen(q.stroke.isValid() ? QPen(q.stroke, q.width) : QPen(Qt::NoPen));
                p.setBrush(q.fill.isValid() ? QBrush(q.fill) : QBrush(Qt::NoBrush));
                p.drawRect(q.rect);
                break;
            case Prim::Polyline: {
                QPen pen(q.stroke, q.width, q.style, Qt::RoundCap, Qt::RoundJoin);
                p.setPen(pen);
                p.setBrush(Qt::NoBrush);
                p.drawPolyline(q.points.data(), static_cast<int>(q.points.size()));
                break;
            }
            case Prim::Marker: {
                p.setPen(QPen(q.stroke, q.shape == MarkerShape::Cross ? 1.8 : 1.0));
                p.setBrush(q.fill.isValid() ? QBrush(q.fill) : QBrush(Qt::NoBrush));
                p.drawPath(markerPath(q.shape, q.points.front(), q.size));
                break;
            }
            case Prim::Text: {
                const QFont font = fontPx(q.fontPx, q.bold);
                p.setFont(font);
                p.setPen(q.fill);
                const double w = QFontMetricsF(font).horizontalAdvance(q.text);
                const double dx = (q.align & Qt::AlignHCenter) ? -w / 2 : (q.align & Qt::AlignRight) ? -w : 0.0;
                p.save();
                p.translate(q.points.front());
                if (q.vertical) p.rotate(-90);
                p.drawText(QPointF(dx, 0), q.text);
                p.restore();
                break;
            }
        }
    }
}

}  // namespace

void PlotWidget::paintEvent(QPaintEvent*) {
    QPainter p(this);
    paintPrimitives(p, primitives(size()));
}

QImage PlotWidget::toImage(double scale) const {
    QImage image((QSizeF(size()) * scale).toSize(), QImage::Format_ARGB32_Premultiplied);
    image.fill(Qt::white);
    QPainter p(&image);
    p.scale(scale, scale);
    paintPrimitives(p, primitives(size()));
    return image;
}

bool PlotWidget::exportPng(const QString& path, double scale) const {
    return toImage(scale).save(path, "PNG");
}

QString PlotWidget::toSvg() const {
    const QSizeF s = size();
    QString out;
    QTextStream o(&out);
    o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << svgNum(s.width()) << "\" height=\"" << svgNum(s.height())
      << "\" viewBox=\"0 0 " << svgNum(s.width()) << ' ' << svgNum(s.height()) << "\" font-family=\"sans-serif\">\n";
    if (!title_.isEmpty()) o << "<title>" << svgEscape(title_) << "</title>\n";
    for (const Primitive& q : primitives(s)) {
        switch (q.kind) {
            case Primitive::Rect:
                o << "<rect x=\"" << svgNum(q.rect.x()) << "\" y=\"" << svgNum(q.rect.y()) << "\" width=\""
                  << svgNum(q.rect.width()) << "\" height=\"" << svgNum(q.rect.height()) << "\" fill=\""
                  << svgColour(q.fill) << '"';
                if (q.fill.isValid() && q.fill.alpha() < 255) o << " fill-opacity=\"" << svgNum(q.fill.alphaF()) << '"';
                o << " stroke=\"" << svgColour(q.stroke) << "\" stroke-width=\"" << svgNum(q.width) << "\"/>\n";
                break;
            case Primitive::Polyline: {
                o << "<polyline fill=\"none\" stroke=\"" << svgColour(q.stroke) << "\" stroke-width=\"" << svgNum(q.width)
                  << "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
                const QString dash = dashArray(q.style, q.width);
                if (!dash.isEmpty()) o << " stroke-dasharray=\"" << dash << '"';
                o << " points=\"";
                for (const QPointF& p : q.points) o << svgNum(p.x()) << ',' << svgNum(p.y()) << ' ';
                o << "\"/>\n";
                break;
            }
            case Primitive::Marker: {
                const QPointF c = q.points.front();
                const double r = q.size / 2;
                const QString stroke = QStringLiteral(" stroke=\"%1\" fill=\"%2\"").arg(svgColour(q.stroke), svgColour(q.fill));
                if (q.shape == MarkerShape::Circle) {
                    o << "<circle cx=\"" << svgNum(c.x()) << "\" cy=\"" << svgNum(c.y()) << "\" r=\"" << svgNum(r) << '"'
                      << stroke << "/>\n";
                } else if (q.shape == MarkerShape::Square) {
                    o << "<rect x=\"" << svgNum(c.x() - r) << "\" y=\"" << svgNum(c.y() - r) << "\" width=\"" << svgNum(q.size)
                      << "\" height=\"" << svgNum(q.size) << '"' << stroke << "/>\n";
                } else {
                    const QPainterPath path = markerPath(q.shape, c, q.size);
                    o << "<path d=\"";
                    for (int i = 0; i < path.elementCount(); ++i) {
                        const QPainterPath::Element e = path.elementAt(i);
                        o << (e.isMoveTo() ? 'M' : 'L') << svgNum(e.x) << ' ' << svgNum(e.y) << ' ';
                    }
                    if (q.shape == MarkerShape::Diamond) o << 'Z';
                    o << '"' << stroke << " stroke-width=\"" << (q.shape == MarkerShape::Cross ? "1.8" : "1") << "\"/>\n";
                }
                break;
            }
            case Primitive::Text: {
                const char* anchor = (q.align & Qt::AlignHCenter) ? "middle" : (q.align & Qt::AlignRight) ? "end" : "start";
                const QPointF at = q.points.front();
                o << "<text x=\"" << svgNum(at.x()) << "\" y=\"" << svgNum(at.y()) << "\" font-size=\"" << svgNum(q.fontPx)
                  << "\" text-anchor=\"" << anchor << "\" fill=\"" << svgColour(q.fill) << '"';
                if (q.bold) o << " font-weight=\"bold\"";
                if (q.vertical) o << " transform=\"rotate(-90 " << svgNum(at.x()) << ' ' << svgNum(at.y()) << ")\"";
                o << '>' << svgEscape(q.text) << "</text>\n";
                break;
            }
        }
    }
    o << "</svg>\n";
    return out;
}

bool PlotWidget::exportSvg(const QString& path) const {
    return saveText(path, toSvg());
}

QString PlotWidget::toCsv() const {
    if (csvWriter_) return csvWriter_();
    auto quoted = [](QString s) { return QLatin1Char('"') + s.replace(QLatin1Char('"'), QStringLiteral("\"\"")) + QLatin1Char('"'); };
    QString out = QStringLiteral("series,%1,%2\n").arg(quoted(axisTitle(x_).isEmpty() ? QStringLiteral("x") : axisTitle(x_)),
                                                      quoted(axisTitle(y_).isEmpty() ? QStringLiteral("y") : axisTitle(y_)));
    for (const PlotSeries& s : series_)
        for (const QPointF& p : s.points) {
            if (std::isnan(p.y())) continue;
            out += QStringLiteral("%1,%2,%3\n").arg(quoted(s.name), QString::number(p.x(), 'g', 17), QString::number(p.y(), 'g', 17));
        }
    return out;
}

bool PlotWidget::exportCsv(const QString& path) const {
    return saveText(path, toCsv());
}

void PlotWidget::exportWithDialog() {
    QString filter;
    QString base = title_.isEmpty() ? QStringLiteral("plot") : title_.toLower();
    base.replace(QRegularExpression(QStringLiteral("[^a-z0-9]+")), QStringLiteral("_"));
    QString path = QFileDialog::getSaveFileName(this, tr("Export Plot"), base + QStringLiteral(".png"),
                                                tr("PNG image (*.png);;SVG drawing (*.svg);;CSV data (*.csv)"), &filter);
    if (path.isEmpty()) return;
    QString suffix = QFileInfo(path).suffix().toLower();
    if (suffix.isEmpty()) {
        suffix = filter.contains(QLatin1String("svg")) ? QStringLiteral("svg")
                 : filter.contains(QLatin1String("csv")) ? QStringLiteral("csv")
                                                         : QStringLiteral("png");
        path += QLatin1Char('.') + suffix;
    }
    const double scale = setting(QStringLiteral("plots/exportScale")).toDouble();
    const bool ok = suffix == QLatin1String("svg")   ? exportSvg(path)
                    : suffix == QLatin1String("csv") ? exportCsv(path)
                                                     : exportPng(path, scale > 0 ? scale : 2.0);
    if (!ok) QMessageBox::critical(this, tr("Cannot export"), tr("Cannot write '%1'.").arg(path));
}

}  // namespace aero::ui
