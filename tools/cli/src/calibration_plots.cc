// The PNGs of `omnidso calibrate`: where the corners lie in the image (coverage decides
// which part of the lens the calibration describes), each model's residual vectors
// magnified (systematic patterns — radial, tangential, per board — show a model that does
// not fit), and the per-view RMS of every model.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <omnidso/cli/calibration_outputs.hpp>
#include <omnidso/cli/line_plot.hpp>
#include <omnidso/core/error.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

constexpr int kCanvasWidth = 1000;
const cv::Scalar kWhite(255, 255, 255), kBlack(0, 0, 0), kGrey(170, 170, 170),
    kRed(40, 40, 220);

void writePng(const fs::path& path, const cv::Mat& image) {
  if (!cv::imwrite(path.string(), image)) throw Error(path.string() + ": cannot write the PNG");
}

// The image frame scaled to kCanvasWidth, with a caption strip below.
struct ImageCanvas {
  double scale;
  cv::Mat mat;
  explicit ImageCanvas(const BoardDetections& d)
      : scale(static_cast<double>(kCanvasWidth) / d.width),
        mat(static_cast<int>(std::lround(d.height * scale)) + 60, kCanvasWidth, CV_8UC3,
            kWhite) {
    cv::rectangle(mat, cv::Rect(0, 0, kCanvasWidth, mat.rows - 60), kBlack, 1);
  }
  cv::Point at(const Eigen::Vector2d& uv) const {
    return {static_cast<int>(std::lround((uv.x() + 0.5) * scale)),
            static_cast<int>(std::lround((uv.y() + 0.5) * scale))};
  }
  void caption(const std::string& line, int row) {
    cv::putText(mat, line, {8, mat.rows - 38 + 22 * row}, cv::FONT_HERSHEY_SIMPLEX, 0.55, kBlack,
                1, cv::LINE_AA);
  }
};

cv::Mat coverage(const CalibrationRun& run) {
  ImageCanvas canvas(run.detections);
  const BoardSpec& b = run.board;
  const CornerSelection& s = run.report.selection;
  for (size_t v = 0; v < run.detections.views.size(); ++v) {
    const std::vector<Eigen::Vector2d>& c = run.detections.views[v].corners;
    const cv::Scalar colour = s.view_used[v] ? seriesColour(v) : kGrey;
    const std::vector<cv::Point> outline = {canvas.at(c[0]), canvas.at(c[b.cols - 1]),
                                            canvas.at(c[b.numCorners() - 1]),
                                            canvas.at(c[b.numCorners() - b.cols])};
    cv::polylines(canvas.mat, outline, true, colour, 1, cv::LINE_AA);
    for (size_t k = 0; k < c.size(); ++k) {
      if (s.view_used[v] && !s.corner_used[v][k]) {
        cv::drawMarker(canvas.mat, canvas.at(c[k]), kRed, cv::MARKER_TILTED_CROSS, 10, 2);
      } else {
        cv::circle(canvas.mat, canvas.at(c[k]), 2, colour, cv::FILLED, cv::LINE_AA);
      }
    }
  }
  canvas.caption(fmt::format("corner coverage: {} views, {} corners used; grey: dropped views, "
                             "red x: outlier corners",
                             s.numViews(), s.numCorners()),
                 0);
  return canvas.mat;
}

cv::Mat residualVectors(const CalibrationRun& run, const ModelCalibration& m) {
  ImageCanvas canvas(run.detections);
  // Magnification: the RMS residual drawn about 12 canvas pixels long, rounded to 1-2-5.
  const double magnification =
      m.rms_px > 0 ? niceTickStep(12.0 / (m.rms_px * canvas.scale), 1) : 1.0;
  const CornerSelection& s = run.report.selection;
  for (size_t v = 0; v < run.detections.views.size(); ++v) {
    if (!s.view_used[v]) continue;
    for (size_t k = 0; k < m.fit.residuals[v].size(); ++k) {
      if (!s.corner_used[v][k] || !m.fit.residuals[v][k].allFinite()) continue;
      const Eigen::Vector2d& uv = run.detections.views[v].corners[k];
      cv::circle(canvas.mat, canvas.at(uv), 1, kGrey, cv::FILLED);
      cv::arrowedLine(canvas.mat, canvas.at(uv),
                      canvas.at(uv + magnification * m.fit.residuals[v][k]), seriesColour(v), 1,
                      cv::LINE_AA, 0, 0.2);
    }
  }
  canvas.caption(fmt::format("{}: residual vectors (projection - detection) x {:g}; RMS {:.4f} "
                             "px, max {:.3f} px",
                             m.fit.camera.modelName(), magnification, m.rms_px, m.max_px),
                 0);
  return canvas.mat;
}

cv::Mat viewRms(const CalibrationRun& run) {
  LinePlot plot("RMS reprojection error per view", "view (file order)", "RMS [px]");
  plot.setIncludeZeroY(true);
  for (size_t i = 0; i < run.report.models.size(); ++i) {
    const ModelCalibration& m = run.report.models[i];
    PlotSeries series{m.fit.camera.modelName(), seriesColour(i), {}, 2, false};
    for (size_t v = 0; v < m.view_rms_px.size(); ++v)
      if (std::isfinite(m.view_rms_px[v]))
        series.points.push_back({static_cast<double>(v), m.view_rms_px[v]});
    plot.addSeries(std::move(series));
  }
  return plot.render(1100, 600);
}

}  // namespace

void writeCalibrationPlots(const std::string& dir, const CalibrationRun& run) {
  writePng(fs::path(dir) / "coverage.png", coverage(run));
  for (const ModelCalibration& m : run.report.models)
    writePng(fs::path(dir) / ("residuals_" + m.fit.camera.modelName() + ".png"),
             residualVectors(run, m));
  writePng(fs::path(dir) / "view_rms.png", viewRms(run));
}

}  // namespace omnidso::cli
