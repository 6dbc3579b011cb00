#pragma once
// Line plots as SVG for the CLI's reports (the gradient check's error against the step, an
// optimization's convergence history): one panel, a polyline with markers per series, axes with
// decade (log) or evenly spaced (linear) grid lines, labels and a legend.
#include <string>
#include <utility>
#include <vector>

namespace aero::app {

struct PlotSeries {
    std::string name;
    std::vector<std::pair<double, double>> points;  // (x, y); on a log axis non-positive values are skipped
};

struct PlotOptions {
    std::string title, xLabel, yLabel;
    bool logX = false, logY = false;
    bool reverseX = false;        // x falls to the right (e.g. a step size)
    double referenceY = 0;        // a dashed horizontal line at this y (e.g. a tolerance) ...
    std::string referenceLabel;   // ... drawn when this is not empty
};

/// Writes the plot to `path` (replacing it atomically). Throws InputError naming the file.
void writeSvgPlot(const std::string& path, const std::vector<PlotSeries>& series, const PlotOptions& o);

}  // namespace aero::app
