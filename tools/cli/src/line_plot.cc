#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <omnidso/cli/line_plot.hpp>
#include <opencv2/imgproc.hpp>

namespace omnidso::cli {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
const cv::Scalar kBlack(0, 0, 0), kGrey(140, 140, 140), kGrid(228, 228, 228);

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) { lo = std::min(lo, v), hi = std::max(hi, v); }
  bool empty() const { return !(lo <= hi); }
  double size() const { return hi - lo; }
  // Non-empty, non-zero width, with a margin on both sides.
  void finish(double margin) {
    if (empty()) lo = 0, hi = 1;
    if (size() <= 0) lo -= 0.5, hi += 0.5;
    const double m = margin * size();
    lo -= m, hi += m;
  }
  void widenTo(double width) {
    const double grow = 0.5 * (width - size());
    if (grow > 0) lo -= grow, hi += grow;
  }
};

int textWidth(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline).width;
}

void text(cv::Mat& image, const std::string& s, cv::Point at, double scale, const cv::Scalar& c) {
  cv::putText(image, s, at, kFont, scale, c, 1, cv::LINE_AA);
}

std::string tickLabel(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  if (std::abs(value) < 0.5 * step * 1e-6) value = 0;  // no "-0.0"
  return fmt::format("{:.{}f}", value, decimals);
}

}  // namespace

LinePlot::LinePlot(std::string title, std::string x_label, std::string y_label)
    : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

cv::Scalar seriesColour(size_t i) {
  static const cv::Scalar palette[] = {
      {180, 119, 31}, {14, 127, 255},  {44, 160, 44},  {40, 39, 214},  {189, 103, 148},
      {75, 86, 140},  {194, 119, 227}, {34, 189, 188}, {207, 190, 23}, {120, 40, 90}};
  return palette[i % (sizeof(palette) / sizeof(palette[0]))];
}

double niceTickStep(double range, int target_ticks) {
  const double raw = range / std::max(1, target_ticks);
  if (!(raw > 0) || !std::isfinite(raw)) return 1.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / magnitude;
  return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * magnitude;
}

cv::Mat LinePlot::render(int width, int height) const {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  // Legend column on the right, as wide as its longest line.
  int legend_width = 0;
  for (const PlotSeries& s : series_)
    legend_width = std::max(legend_width, textWidth(s.label, 0.45));
  for (const std::string& n : notes_) legend_width = std::max(legend_width, textWidth(n, 0.45));
  legend_width = std::min(legend_width + 50, width / 2);
  const cv::Rect area(75, 65, std::max(50, width - 75 - legend_width - 25),
                      std::max(50, height - 65 - 55));

  Range x, y;
  for (const PlotSeries& s : series_)
    for (const cv::Point2d& p : s.points) x.add(p.x), y.add(p.y);
  if (include_zero_y_) y.add(0.0);
  x.finish(0.03);
  y.finish(0.05);
  if (equal_aspect_) {
    const double metres_per_pixel = std::max(x.size() / area.width, y.size() / area.height);
    x.widenTo(metres_per_pixel * area.width);
    y.widenTo(metres_per_pixel * area.height);
  }
  auto toPixel = [&](const cv::Point2d& p) {
    return cv::Point(static_cast<int>(std::lround(area.x + (p.x - x.lo) / x.size() * area.width)),
                     static_cast<int>(std::lround(area.y + (y.hi - p.y) / y.size() * area.height)));
  };

  // Grid and tick labels.
  const double x_step = niceTickStep(x.size(), 8), y_step = niceTickStep(y.size(), 6);
  for (double v = std::ceil(x.lo / x_step) * x_step; v <= x.hi; v += x_step) {
    const int u = toPixel({v, y.lo}).x;
    cv::line(image, {u, area.y}, {u, area.y + area.height}, kGrid, 1);
    const std::string label = tickLabel(v, x_step);
    text(image, label, {u - textWidth(label, 0.4) / 2, area.y + area.height + 18}, 0.4, kBlack);
  }
  for (double v = std::ceil(y.lo / y_step) * y_step; v <= y.hi; v += y_step) {
    const int row = toPixel({x.lo, v}).y;
    cv::line(image, {area.x, row}, {area.x + area.width, row}, kGrid, 1);
    const std::string label = tickLabel(v, y_step);
    text(image, label, {area.x - 8 - textWidth(label, 0.4), row + 5}, 0.4, kBlack);
  }
  cv::rectangle(image, area, kBlack, 1);
  text(image, x_label_, {area.x + area.width / 2 - textWidth(x_label_, 0.5) / 2, height - 15}, 0.5,
       kBlack);
  text(image, y_label_, {10, area.y - 10}, 0.5, kBlack);
  text(image, title_, {10, 26}, 0.6, kBlack);

  // Curves, then the legend.
  for (const PlotSeries& s : series_) {
    std::vector<cv::Point> pixels;
    for (const cv::Point2d& p : s.points) pixels.push_back(toPixel(p));
    if (pixels.size() >= 2) cv::polylines(image, pixels, false, s.colour, s.thickness, cv::LINE_AA);
    if (!pixels.empty() && (s.mark_start || pixels.size() == 1))
      cv::circle(image, pixels.front(), 5, s.colour, 2, cv::LINE_AA);
  }
  int row = area.y + 12;
  const int left = area.x + area.width + 20;
  for (const PlotSeries& s : series_) {
    cv::line(image, {left, row - 4}, {left + 24, row - 4}, s.colour, std::max(2, s.thickness),
             cv::LINE_AA);
    text(image, s.label, {left + 32, row}, 0.45, kBlack);
    row += 22;
  }
  for (const std::string& n : notes_) {
    text(image, n, {left + 32, row}, 0.45, kGrey);
    row += 22;
  }
  return image;
}

}  // namespace omnidso::cli
