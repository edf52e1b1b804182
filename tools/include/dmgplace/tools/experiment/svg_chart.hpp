#pragma once
// A small SVG line chart writer: lines with an optional shaded band (mean +- standard error),
// axes with ticks, a legend. Points with a NaN value break the line.
#include <limits>
#include <string>
#include <vector>

namespace dmgplace::tools {

struct ChartSeries {
  std::string label;
  std::string color;           // any SVG colour
  std::vector<double> x, y;    // same length
  std::vector<double> lo, hi;  // optional band, same length as x (NaN: none)
};

struct ChartOptions {
  std::string title, x_label, y_label;
  int width = 720, height = 420;
  bool y_from_zero = false;
  double y_max = std::numeric_limits<double>::quiet_NaN();  // fixed top (NaN: from the data)
};

std::string line_chart_svg(const std::vector<ChartSeries>& series, const ChartOptions& options);

}  // namespace dmgplace::tools
