#include "cli/SvgPlot.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/AtomicFile.h"

namespace aero::app {

namespace {

// One axis: the data range mapped to [from, to] pixels, in decades or linearly.
struct Axis {
    bool log = false;
    double lo = 0, hi = 1;  // in decades when log
    double from = 0, to = 1;
    double map(double v) const {
        const double t = ((log ? std::log10(v) : v) - lo) / (hi - lo);
        return from + (to - from) * t;
    }
    // Grid values: every decade, or about 6 round steps.
    std::vector<double> ticks() const {
        std::vector<double> t;
        if (log) {
            for (double e = lo; e <= hi + 1e-9; e += 1) t.push_back(std::pow(10.0, e));
            return t;
        }
        const double raw = (hi - lo) / 6;
        const double mag = std::pow(10.0, std::floor(std::log10(raw)));
        const double step = raw / mag < 2 ? 2 * mag : (raw / mag < 5 ? 5 * mag : 10 * mag);
        for (double v = std::ceil(lo / step) * step; v <= hi + 1e-12 * std::abs(hi); v += step) t.push_back(v);
        return t;
    }
    std::string label(double v) const {
        std::ostringstream s;
        if (log) s << "1e" << std::lround(std::log10(v));
        else s << (std::abs(v) < 1e-9 * (std::abs(hi) + std::abs(lo)) ? 0.0 : v);
        return s.str();
    }
};

Axis makeAxis(bool log, double lo, double hi, double from, double to) {
    Axis a;
    a.log = log;
    a.from = from;
    a.to = to;
    if (log) {
        a.lo = std::floor(std::log10(lo));
        a.hi = std::max(a.lo + 1, std::ceil(std::log10(hi)));
    } else {
        const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(1e-12, 0.05 * std::abs(hi) + 1e-12);
        a.lo = lo - pad;
        a.hi = hi + pad;
    }
    return a;
}

}  // namespace

void writeSvgPlot(const std::string& path, const std::vector<PlotSeries>& series, const PlotOptions& o) {
    const double W = 760, H = 520, L = 90, R = 190, T = 40, B = 60;
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    auto usable = [&](double x, double y) {
        return std::isfinite(x) && std::isfinite(y) && (!o.logX || x > 0) && (!o.logY || y > 0);
    };
    for (const PlotSeries& s : series) {
        for (const auto& [x, y] : s.points) {
            if (!usable(x, y)) continue;
            xmin = std::min(xmin, x);
            xmax = std::max(xmax, x);
            ymin = std::min(ymin, y);
            ymax = std::max(ymax, y);
        }
    }
    if (!o.referenceLabel.empty() && (!o.logY || o.referenceY > 0)) {
        ymin = std::min(ymin, o.referenceY);
        ymax = std::max(ymax, o.referenceY);
    }
    if (xmin > xmax) xmin = 0, xmax = 1;
    if (ymin > ymax) ymin = o.logY ? 1e-1 : 0, ymax = o.logY ? 1 : 1;
    const Axis X = makeAxis(o.logX, xmin, xmax, o.reverseX ? W - R : L, o.reverseX ? L : W - R);
    const Axis Y = makeAxis(o.logY, ymin, ymax, H - B, T);
    std::ostringstream s;
    s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H << "' font-family='sans-serif' font-size='12'>\n";
    s << "<rect width='100%' height='100%' fill='white'/>\n";
    for (double v : X.ticks()) {
        s << "<line x1='" << X.map(v) << "' y1='" << T << "' x2='" << X.map(v) << "' y2='" << H - B
          << "' stroke='#ddd'/><text x='" << X.map(v) << "' y='" << H - B + 18 << "' text-anchor='middle'>" << X.label(v)
          << "</text>\n";
    }
    for (double v : Y.ticks()) {
        s << "<line x1='" << L << "' y1='" << Y.map(v) << "' x2='" << W - R << "' y2='" << Y.map(v)
          << "' stroke='#ddd'/><text x='" << L - 6 << "' y='" << Y.map(v) + 4 << "' text-anchor='end'>" << Y.label(v)
          << "</text>\n";
    }
    s << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B
      << "' fill='none' stroke='black'/>\n";
    if (!o.referenceLabel.empty() && (!o.logY || o.referenceY > 0)) {
        s << "<line x1='" << L << "' y1='" << Y.map(o.referenceY) << "' x2='" << W - R << "' y2='" << Y.map(o.referenceY)
          << "' stroke='red' stroke-dasharray='6,4'/><text x='" << W - R + 6 << "' y='" << Y.map(o.referenceY) + 4
          << "' fill='red'>" << o.referenceLabel << "</text>\n";
    }
    s << "<text x='" << (W - R + L) / 2 << "' y='" << H - 15 << "' text-anchor='middle'>" << o.xLabel << "</text>\n";
    s << "<text x='22' y='" << (H - B + T) / 2 << "' transform='rotate(-90 22 " << (H - B + T) / 2
      << ")' text-anchor='middle'>" << o.yLabel << "</text>\n";
    s << "<text x='" << L << "' y='24' font-size='14'>" << o.title << "</text>\n";
    const char* colours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2"};
    for (std::size_t k = 0; k < series.size(); ++k) {
        const char* col = colours[k % 7];
        s << "<polyline fill='none' stroke='" << col << "' stroke-width='2' points='";
        for (const auto& [x, y] : series[k].points) {
            if (usable(x, y)) s << X.map(x) << "," << Y.map(y) << " ";
        }
        s << "'/>\n";
        for (const auto& [x, y] : series[k].points) {
            if (usable(x, y)) s << "<circle cx='" << X.map(x) << "' cy='" << Y.map(y) << "' r='3' fill='" << col << "'/>\n";
        }
        s << "<text x='" << W - R + 6 << "' y='" << T + 16 + 18 * k << "' fill='" << col << "'>" << series[k].name << "</text>\n";
    }
    s << "</svg>\n";
    writeTextAtomically(path, s.str(), "plot file");
}

}  // namespace aero::app
