#include "dmgplace/tools/experiment/svg_chart.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace dmgplace::tools {
namespace {
std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

// Round tick spacing: 1, 2 or 5 times a power of ten, about `n` ticks over the span.
double tick_step(double span, int n) {
  const double raw = span / std::max(1, n);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * p) return m * p;
  return 10 * p;
}
}  // namespace

namespace {
// The data's range (padded, as the options ask) and where the plot sits in the picture.
struct Frame {
  double x0, x1, y0, y1;  // data
  double L, T, W, H;      // plot area (px): left, top, width, height
  double px(double x) const { return L + (x - x0) / (x1 - x0) * W; }
  double py(double y) const { return T + (1 - (y - y0) / (y1 - y0)) * H; }
};

Frame frame_of(const std::vector<ChartSeries>& series, const ChartOptions& o) {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
      for (double v : {s.y[i], i < s.lo.size() ? s.lo[i] : NAN, i < s.hi.size() ? s.hi[i] : NAN})
        if (std::isfinite(v)) y0 = std::min(y0, v), y1 = std::max(y1, v);
    }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1;
  if (!std::isfinite(y0)) y0 = 0, y1 = 1;
  if (o.y_from_zero) y0 = std::min(0.0, y0);
  if (std::isfinite(o.y_max)) y1 = o.y_max;
  if (y1 - y0 < 1e-12) y1 = y0 + 1;
  if (x1 - x0 < 1e-12) x1 = x0 + 1;
  const double pad = 0.05 * (y1 - y0);
  if (!o.y_from_zero) y0 -= pad;
  if (!std::isfinite(o.y_max)) y1 += pad;
  // The legend sits right of the plot: room for its longest label (about 7 px a character at 12 px).
  std::size_t longest = 0;
  for (const auto& se : series) longest = std::max(longest, se.label.size());
  const double L = 70, R = std::max(170.0, 60.0 + 7.0 * double(longest)), T = 40, B = 55;
  return {x0, x1, y0, y1, L, T, o.width - L - R, o.height - T - B};
}

// Title, grid, ticks, the plot's box and the axis labels.
void write_axes(std::ostringstream& s, const Frame& f, const ChartOptions& o) {
  const double L = f.L, T = f.T, W = f.W, H = f.H;
  s << "<text x=\"" << o.width / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">" << escape(o.title)
    << "</text>\n";
  const double xs = tick_step(f.x1 - f.x0, 8), ys = tick_step(f.y1 - f.y0, 6);
  for (double x = std::ceil(f.x0 / xs) * xs; x <= f.x1 + 1e-9; x += xs)
    s << "<line x1=\"" << f.px(x) << "\" y1=\"" << T << "\" x2=\"" << f.px(x) << "\" y2=\"" << T + H
      << "\" stroke=\"#e4e4e4\"/>"
      << "<text x=\"" << f.px(x) << "\" y=\"" << T + H + 16 << "\" text-anchor=\"middle\">" << x << "</text>\n";
  for (double y = std::ceil(f.y0 / ys) * ys; y <= f.y1 + 1e-9; y += ys)
    s << "<line x1=\"" << L << "\" y1=\"" << f.py(y) << "\" x2=\"" << L + W << "\" y2=\"" << f.py(y)
      << "\" stroke=\"#e4e4e4\"/>"
      << "<text x=\"" << L - 6 << "\" y=\"" << f.py(y) + 4 << "\" text-anchor=\"end\">" << (std::abs(y) < 1e-12 ? 0 : y)
      << "</text>\n";
  s << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W << "\" height=\"" << H
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  s << "<text x=\"" << L + W / 2 << "\" y=\"" << o.height - 14 << "\" text-anchor=\"middle\">" << escape(o.x_label)
    << "</text>\n";
  s << "<text transform=\"translate(18," << T + H / 2 << ") rotate(-90)\" text-anchor=\"middle\">" << escape(o.y_label)
    << "</text>\n";
}

// A series' band between lo and hi, split where either is missing.
void write_band(std::ostringstream& s, const ChartSeries& se, const Frame& f) {
  std::vector<std::pair<double, double>> up, down;
  auto flush = [&] {
    if (up.size() >= 2) {
      s << "<polygon fill=\"" << se.color << "\" fill-opacity=\"0.18\" stroke=\"none\" points=\"";
      for (auto [x, y] : up) s << f.px(x) << ',' << f.py(y) << ' ';
      for (auto it = down.rbegin(); it != down.rend(); ++it) s << f.px(it->first) << ',' << f.py(it->second) << ' ';
      s << "\"/>\n";
    }
    up.clear();
    down.clear();
  };
  for (std::size_t i = 0; i < se.x.size() && i < se.lo.size() && i < se.hi.size(); ++i) {
    if (std::isfinite(se.lo[i]) && std::isfinite(se.hi[i])) {
      up.emplace_back(se.x[i], std::clamp(se.hi[i], f.y0, f.y1));
      down.emplace_back(se.x[i], std::clamp(se.lo[i], f.y0, f.y1));
    } else {
      flush();
    }
  }
  flush();
}

// A series' line, split at missing values.
void write_line(std::ostringstream& s, const ChartSeries& se, const Frame& f) {
  std::ostringstream pts;
  auto flush = [&] {
    if (!pts.str().empty())
      s << "<polyline fill=\"none\" stroke=\"" << se.color << "\" stroke-width=\"2\" points=\"" << pts.str()
        << "\"/>\n";
    pts.str("");
  };
  for (std::size_t i = 0; i < se.x.size(); ++i) {
    if (std::isfinite(se.y[i])) pts << f.px(se.x[i]) << ',' << f.py(se.y[i]) << ' ';
    else flush();
  }
  flush();
}
}  // namespace

std::string line_chart_svg(const std::vector<ChartSeries>& series, const ChartOptions& o) {
  const Frame f = frame_of(series, o);
  std::ostringstream s;
  s.precision(6);
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.width << "\" height=\"" << o.height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  write_axes(s, f, o);
  for (const auto& se : series) write_band(s, se, f);  // bands first, lines over them
  for (const auto& se : series) write_line(s, se, f);
  for (std::size_t k = 0; k < series.size(); ++k) {
    const double y = f.T + 10 + 20 * double(k);
    s << "<line x1=\"" << f.L + f.W + 12 << "\" y1=\"" << y << "\" x2=\"" << f.L + f.W + 36 << "\" y2=\"" << y
      << "\" stroke=\"" << series[k].color << "\" stroke-width=\"3\"/><text x=\"" << f.L + f.W + 42 << "\" y=\""
      << y + 4 << "\">" << escape(series[k].label) << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace dmgplace::tools
