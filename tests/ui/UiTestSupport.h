#pragma once
// Shared helpers of the GUI tests: screenshot folder (a CI artifact in the build tree), image
// comparison, synthetic mouse events sent through the same path as real ones.
#include <QApplication>
#include <QImage>
#include <QMouseEvent>
#include <QSet>
#include <QString>
#include <QWidget>
#include <algorithm>
#include <cmath>

namespace aero::uitest {

inline const QString kScreenshotDir = QStringLiteral(AEROFORM_UI_SCREENSHOT_DIR);

struct PixelStats {
    double differingShare = 0;  // share of pixels that differ from the reference
    double meanLuma = 0;        // over the differing pixels
    double lumaStdDev = 0;      // over the differing pixels (shading varies across a sphere)
};

inline int luma(QRgb c) {
    return (299 * qRed(c) + 587 * qGreen(c) + 114 * qBlue(c)) / 1000;
}

// Compares two frames of the same size pixel by pixel; a pixel "differs" when any channel
// differs by more than `tolerance`.
inline PixelStats compare(const QImage& image, const QImage& reference, int tolerance = 24) {
    PixelStats s;
    const QImage a = image.convertToFormat(QImage::Format_RGB32);
    const QImage b = reference.convertToFormat(QImage::Format_RGB32);
    long long count = 0;
    double sum = 0, sum2 = 0;
    for (int y = 0; y < a.height(); ++y) {
        const auto* ra = reinterpret_cast<const QRgb*>(a.constScanLine(y));
        const auto* rb = reinterpret_cast<const QRgb*>(b.constScanLine(y));
        for (int x = 0; x < a.width(); ++x) {
            const int d = std::max({std::abs(qRed(ra[x]) - qRed(rb[x])), std::abs(qGreen(ra[x]) - qGreen(rb[x])),
                                    std::abs(qBlue(ra[x]) - qBlue(rb[x]))});
            if (d > tolerance) {
                ++count;
                const double l = luma(ra[x]);
                sum += l;
                sum2 += l * l;
            }
        }
    }
    const double n = static_cast<double>(a.width()) * a.height();
    s.differingShare = n > 0 ? static_cast<double>(count) / n : 0;
    if (count > 0) {
        s.meanLuma = sum / static_cast<double>(count);
        s.lumaStdDev = std::sqrt(std::max(0.0, sum2 / static_cast<double>(count) - s.meanLuma * s.meanLuma));
    }
    return s;
}

// Share of pixels that are strongly red (r high, g and b low): the highlight colour.
inline double redShare(const QImage& image) {
    const QImage a = image.convertToFormat(QImage::Format_RGB32);
    long long count = 0;
    for (int y = 0; y < a.height(); ++y) {
        const auto* row = reinterpret_cast<const QRgb*>(a.constScanLine(y));
        for (int x = 0; x < a.width(); ++x)
            if (qRed(row[x]) > 170 && qGreen(row[x]) < 90 && qBlue(row[x]) < 90) ++count;
    }
    return static_cast<double>(count) / (static_cast<double>(a.width()) * a.height());
}

// Number of distinct colours (capped), a cheap "not blank" measure for whole-window grabs.
inline int distinctColours(const QImage& image, int cap = 5000) {
    const QImage a = image.convertToFormat(QImage::Format_RGB32);
    QSet<QRgb> seen;
    for (int y = 0; y < a.height(); y += 2) {
        const auto* row = reinterpret_cast<const QRgb*>(a.constScanLine(y));
        for (int x = 0; x < a.width(); x += 2) {
            seen.insert(row[x]);
            if (seen.size() >= cap) return cap;
        }
    }
    return static_cast<int>(seen.size());
}

inline void sendMouse(QWidget* w, QEvent::Type type, QPointF pos, Qt::MouseButton button, Qt::MouseButtons buttons,
                      Qt::KeyboardModifiers mods = Qt::NoModifier) {
    QMouseEvent e(type, pos, w->mapToGlobal(pos), button, buttons, mods);
    QApplication::sendEvent(w, &e);
}

// A left-button drag from `from` to `to` in `steps` moves, like a user's.
inline void drag(QWidget* w, QPointF from, QPointF to, int steps = 8, Qt::KeyboardModifiers mods = Qt::NoModifier) {
    sendMouse(w, QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton, mods);
    for (int k = 1; k <= steps; ++k)
        sendMouse(w, QEvent::MouseMove, from + (to - from) * (static_cast<double>(k) / steps), Qt::NoButton, Qt::LeftButton,
                  mods);
    sendMouse(w, QEvent::MouseButtonRelease, to, Qt::LeftButton, Qt::NoButton, mods);
}

inline void click(QWidget* w, QPointF at, Qt::KeyboardModifiers mods = Qt::NoModifier) {
    sendMouse(w, QEvent::MouseButtonPress, at, Qt::LeftButton, Qt::LeftButton, mods);
    sendMouse(w, QEvent::MouseButtonRelease, at, Qt::LeftButton, Qt::NoButton, mods);
}

}  // namespace aero::uitest
