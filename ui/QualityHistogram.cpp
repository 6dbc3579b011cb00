#include "QualityHistogram.h"

#include <QFontMetrics>
#include <QHelpEvent>
#include <QLocale>
#include <QPainter>
#include <QToolTip>
#include <algorithm>
#include <cmath>

namespace aero::ui {

namespace {

QString number(double v) {
    return QLocale().toString(v, 'g', 3);
}

}  // namespace

QualityHistogram::QualityHistogram(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("qualityHistogram"));
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Preferred);
    setMouseTracking(true);
}

void QualityHistogram::setData(std::vector<long> counts, std::vector<QColor> colours, double lo,
                               double hi, bool logScale, const QString& caption) {
    counts_ = std::move(counts);
    colours_ = std::move(colours);
    colours_.resize(counts_.size(), palette().color(QPalette::Highlight));
    lo_ = lo;
    hi_ = hi;
    log_ = logScale && lo > 0 && hi > lo;
    caption_ = caption;
    update();
}

double QualityHistogram::edge(int i) const {
    const double t =
        counts_.empty() ? 0.0 : static_cast<double>(i) / static_cast<double>(counts_.size());
    return log_ ? lo_ * std::pow(hi_ / lo_, t) : lo_ + t * (hi_ - lo_);
}

void QualityHistogram::clear() {
    counts_.clear();
    colours_.clear();
    caption_.clear();
    update();
}

QRectF QualityHistogram::plotArea() const {
    const QFontMetrics fm(font());
    const qreal top = fm.height() * 0.9 + 2;     // counts above the bars
    const qreal bottom = 2.0 * fm.height() + 6;  // range and caption below
    return QRectF(4, top, std::max(10, width() - 8), std::max<qreal>(10, height() - top - bottom));
}

int QualityHistogram::binAt(const QPointF& pos) const {
    const QRectF area = plotArea();
    if (counts_.empty() || !area.adjusted(0, -area.top(), 0, 0).contains(pos)) return -1;
    const int bin = static_cast<int>((pos.x() - area.left()) / area.width() *
                                     static_cast<double>(counts_.size()));
    return std::clamp(bin, 0, static_cast<int>(counts_.size()) - 1);
}

bool QualityHistogram::event(QEvent* e) {
    if (e->type() == QEvent::ToolTip) {
        auto* help = static_cast<QHelpEvent*>(e);
        const int b = binAt(help->pos());
        if (b < 0) {
            QToolTip::hideText();
            e->ignore();
            return true;
        }
        const long n = counts_[static_cast<std::size_t>(b)];
        const QString range = tr("%1 to %2").arg(number(edge(b)), number(edge(b + 1)));
        QToolTip::showText(help->globalPos(),
                           tr("%1: %2 %3")
                               .arg(range, QLocale().toString(static_cast<qlonglong>(n)),
                                    n == 1 ? tr("cell") : tr("cells")),
                           this);
        return true;
    }
    return QWidget::event(e);
}

void QualityHistogram::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.setRenderHint(QPainter::Antialiasing, false);
    const QRectF area = plotArea();
    const QColor text =
        palette().color(isEnabled() ? QPalette::Active : QPalette::Disabled, QPalette::WindowText);
    QColor axis = text;
    axis.setAlphaF(0.45);
    p.setPen(axis);
    p.drawLine(area.bottomLeft(), area.bottomRight());
    if (counts_.empty()) {
        p.setPen(text);
        p.drawText(area, Qt::AlignCenter | Qt::TextWordWrap, tr("No grid yet"));
        return;
    }
    const long largest = *std::max_element(counts_.begin(), counts_.end());
    const double top = std::log10(1.0 + static_cast<double>(std::max(1L, largest)));
    const int n = static_cast<int>(counts_.size());
    const qreal slot = area.width() / n;
    QFont small = font();
    small.setPointSizeF(std::max(6.0, font().pointSizeF() * 0.8));
    const QFontMetrics fm(small);
    p.setFont(small);
    for (int b = 0; b < n; ++b) {
        const long c = counts_[static_cast<std::size_t>(b)];
        const qreal h =
            c > 0 ? std::max<qreal>(2.0,
                                    area.height() * std::log10(1.0 + static_cast<double>(c)) / top)
                  : 0.0;
        const QRectF bar(area.left() + b * slot + 1, area.bottom() - h, slot - 2, h);
        QColor fill = colours_[static_cast<std::size_t>(b)];
        if (!isEnabled()) fill.setAlphaF(0.35f);  // an outdated preview
        p.fillRect(bar, fill);
        p.setPen(axis);
        if (h > 0) p.drawRect(bar);
        if (c > 0) {
            const QString label =
                c >= 10000 ? QStringLiteral("%1k").arg(std::lround(static_cast<double>(c) / 1000.0))
                           : QString::number(c);
            if (fm.horizontalAdvance(label) <= slot + 2) {
                p.setPen(text);
                p.drawText(
                    QRectF(bar.left() - 2, bar.top() - fm.height() - 1, slot + 2, fm.height()),
                    Qt::AlignHCenter | Qt::AlignBottom, label);
            }
        }
    }
    p.setFont(font());
    p.setPen(text);
    const QFontMetrics big(font());
    const QRectF range(area.left(), area.bottom() + 2, area.width(), big.height());
    p.drawText(range, Qt::AlignLeft | Qt::AlignTop, number(lo_));
    p.drawText(range, Qt::AlignRight | Qt::AlignTop, number(hi_));
    p.drawText(QRectF(area.left(), range.bottom() + 2, area.width(), big.height()),
               Qt::AlignHCenter | Qt::AlignTop,
               log_ ? tr("%1 (log axis) \u2014 cells per bin").arg(caption_)
                    : tr("%1 \u2014 cells per bin").arg(caption_));
}

}  // namespace aero::ui
