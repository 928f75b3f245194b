#pragma once

// SVG line plots for the bench's figures in docs/ (no plotting library: a few polylines).

#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace orbis::bench {

struct Series {
    std::string name;
    std::string colour;
    bool dashed = false;
    std::vector<std::pair<double, double>> points; ///< x, y (> 0 on a logarithmic axis)
};

struct PlotAxis {
    std::string label;
    double minimum = 1.0;
    double maximum = 10.0;
    bool logarithmic = true;
    /// Linear axes: a tick every `step`; logarithmic ones tick at the powers of ten.
    double step = 1.0;
    std::function<std::string(double)> tickName; ///< the value's label at a tick
};

/// One panel of an SVG at (x0, y0), w x h: the series as polylines, clamped to the y axis's range,
/// a legend below.
void plotPanel(std::ostringstream& svg, double x0, double y0, double w, double h, const std::string& title,
               const PlotAxis& x, const PlotAxis& y, const std::vector<Series>& series);

} // namespace orbis::bench
