#include "Plot.h"

#include <algorithm>
#include <cmath>

namespace orbis::bench {
namespace {

/// 0 at the axis's minimum, 1 at its maximum.
double fraction(const PlotAxis& axis, double value)
{
    const double v = std::clamp(value, axis.minimum, axis.maximum);
    return axis.logarithmic ? (std::log10(v) - std::log10(axis.minimum)) / (std::log10(axis.maximum) - std::log10(axis.minimum))
                            : (v - axis.minimum) / (axis.maximum - axis.minimum);
}

std::vector<double> ticks(const PlotAxis& axis)
{
    std::vector<double> values;
    if (axis.logarithmic) {
        for (int e = static_cast<int>(std::ceil(std::log10(axis.minimum))); e <= static_cast<int>(std::floor(std::log10(axis.maximum))); ++e) {
            values.push_back(std::pow(10.0, e));
        }
    } else {
        for (double v = std::ceil(axis.minimum / axis.step) * axis.step; v <= axis.maximum + 1e-9 * axis.step; v += axis.step) {
            values.push_back(v);
        }
    }
    return values;
}

} // namespace

void plotPanel(std::ostringstream& svg, double x0, double y0, double w, double h, const std::string& title,
               const PlotAxis& x, const PlotAxis& y, const std::vector<Series>& series)
{
    const double left = x0 + 70;
    const double top = y0 + 40;
    const double width = w - 90;
    const double height = h - 190;
    auto px = [&](double value) { return left + width * fraction(x, value); };
    auto py = [&](double value) { return top + height * (1.0 - fraction(y, value)); };
    svg << "<text x='" << x0 + w / 2 << "' y='" << y0 + 22 << "' text-anchor='middle' font-size='15' font-weight='bold'>"
        << title << "</text>\n";
    svg << "<rect x='" << left << "' y='" << top << "' width='" << width << "' height='" << height
        << "' fill='none' stroke='#444'/>\n";
    for (const double tick : ticks(x)) {
        svg << "<line x1='" << px(tick) << "' y1='" << top << "' x2='" << px(tick) << "' y2='" << top + height
            << "' stroke='#ddd'/>\n<text x='" << px(tick) << "' y='" << top + height + 16
            << "' text-anchor='middle' font-size='11'>" << x.tickName(tick) << "</text>\n";
    }
    for (const double tick : ticks(y)) {
        svg << "<line x1='" << left << "' y1='" << py(tick) << "' x2='" << left + width << "' y2='" << py(tick)
            << "' stroke='#ddd'/>\n<text x='" << left - 6 << "' y='" << py(tick) + 4
            << "' text-anchor='end' font-size='11'>" << y.tickName(tick) << "</text>\n";
    }
    svg << "<text x='" << left + width / 2 << "' y='" << top + height + 34 << "' text-anchor='middle' font-size='12'>"
        << x.label << "</text>\n";
    svg << "<text transform='translate(" << x0 + 16 << "," << top + height / 2
        << ") rotate(-90)' text-anchor='middle' font-size='12'>" << y.label << "</text>\n";
    for (std::size_t k = 0; k < series.size(); ++k) {
        const Series& s = series[k];
        svg << "<polyline fill='none' stroke='" << s.colour << "' stroke-width='" << (s.points.size() > 400 ? 1 : 2) << "'"
            << (s.dashed ? " stroke-dasharray='6,4'" : "") << " points='";
        for (const auto& [vx, vy] : s.points) {
            if (std::isfinite(vy) && (!y.logarithmic || vy > 0.0)) {
                svg << px(vx) << "," << py(vy) << " ";
            }
        }
        svg << "'/>\n";
        const double lx = left + static_cast<double>(k % 2) * width / 2;
        const double ly = top + height + 52 + static_cast<double>(k / 2) * 16;
        svg << "<line x1='" << lx << "' y1='" << ly - 4 << "' x2='" << lx + 24 << "' y2='" << ly - 4 << "' stroke='"
            << s.colour << "' stroke-width='2'" << (s.dashed ? " stroke-dasharray='6,4'" : "") << "/>\n<text x='"
            << lx + 30 << "' y='" << ly << "' font-size='11'>" << s.name << "</text>\n";
    }
}

} // namespace orbis::bench
