#pragma once
// A small line-plot renderer on OpenCV images (imgproc drawing only): axes with 1-2-5
// ticks and grid, axis labels, a title, and a legend to the right of the plot area.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

struct PlotSeries {
  std::string label;
  cv::Scalar colour;  // BGR
  std::vector<cv::Point2d> points;
  int thickness = 2;
  bool mark_start = false;  // a circle on the first point
};

class LinePlot {
 public:
  LinePlot(std::string title, std::string x_label, std::string y_label);

  // Top views: one metre is as long on both axes.
  void setEqualAspect(bool equal) { equal_aspect_ = equal; }
  // The y range always includes 0 (error plots).
  void setIncludeZeroY(bool include) { include_zero_y_ = include; }
  void addSeries(PlotSeries series) { series_.push_back(std::move(series)); }
  // A legend line without a curve, in grey (e.g. "pinhole-crop:90 Kf3: failed 2/2").
  void addLegendNote(std::string text) { notes_.push_back(std::move(text)); }

  cv::Mat render(int width, int height) const;  // 8-bit BGR

 private:
  std::string title_, x_label_, y_label_;
  bool equal_aspect_ = false;
  bool include_zero_y_ = false;
  std::vector<PlotSeries> series_;
  std::vector<std::string> notes_;
};

// Distinct colours for series i = 0, 1, … (cycling), none of them black or grey.
cv::Scalar seriesColour(size_t i);

// A step of 1, 2 or 5 × 10^k near range / target_ticks.
double niceTickStep(double range, int target_ticks);

}  // namespace omnidso::cli
