#include <fmt/core.h>

#include <filesystem>
#include <omnidso/cli/ablation_plots.hpp>
#include <omnidso/cli/line_plot.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <opencv2/imgcodecs.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 1100, kHeight = 760;

void writePng(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw Error(path + ": cannot write the PNG");
}

const char* axisName(int axis) { return axis == 0 ? "x [m]" : axis == 1 ? "y [m]" : "z [m]"; }

}  // namespace

std::pair<int, int> topViewAxes(const Trajectory& trajectory) {
  if (trajectory.empty()) return {0, 1};
  const Eigen::Matrix3Xd p = positions(trajectory);
  const Eigen::Vector3d extent = p.rowwise().maxCoeff() - p.rowwise().minCoeff();
  int smallest = 0;
  extent.minCoeff(&smallest);
  return smallest == 0 ? std::pair{1, 2} : smallest == 1 ? std::pair{0, 2} : std::pair{0, 1};
}

std::vector<std::string> writeDatasetPlots(const std::string& plots_dir, const DatasetPlots& in) {
  fs::create_directories(plots_dir);
  const auto [a, b] = topViewAxes(in.ground_truth);
  LinePlot top(in.name + ": top view, keyframes after Sim(3) alignment (circles: start)",
               axisName(a), axisName(b));
  top.setEqualAspect(true);
  LinePlot ate(in.name + ": keyframe ATE over time (median-RMSE run)", "time [s]", "ATE [m]");
  ate.setIncludeZeroY(true);

  const double t0 = in.ground_truth.empty() ? 0.0 : in.ground_truth.front().timestamp;
  PlotSeries gt{"ground truth", cv::Scalar(0, 0, 0), {}, 2, true};
  for (const StampedPose& p : in.ground_truth)
    gt.points.push_back({p.pose.translation()(a), p.pose.translation()(b)});
  top.addSeries(gt);

  for (size_t m = 0; m < in.methods.size(); ++m) {
    const PlottedMethod& method = in.methods[m];
    if (!method.keyframes) {
      top.addLegendNote(method.label);
      ate.addLegendNote(method.label);
      continue;
    }
    EvaluationResult r;
    try {
      EvaluationOptions options;
      options.alignment = AlignmentType::kSim3;
      options.max_dt = in.max_dt;
      r = evaluate(in.ground_truth, *method.keyframes, options);
    } catch (const Error& e) {
      top.addLegendNote(method.label + ": " + e.what());
      ate.addLegendNote(method.label + ": " + e.what());
      continue;
    }
    PlotSeries path{method.label, seriesColour(m), {}, 2, true};
    for (const StampedPose& p : *method.keyframes) {
      const Eigen::Vector3d aligned = r.alignment * p.pose.translation();
      path.points.push_back({aligned(a), aligned(b)});
    }
    PlotSeries errors{method.label, seriesColour(m), {}, 2, false};
    for (size_t k = 0; k < r.association.size(); ++k)
      errors.points.push_back(
          {in.ground_truth[r.association[k].first].timestamp - t0, r.position_errors[k]});
    top.addSeries(std::move(path));
    ate.addSeries(std::move(errors));
  }
  const std::vector<std::string> paths = {
      (fs::path(plots_dir) / (in.name + "_trajectories.png")).string(),
      (fs::path(plots_dir) / (in.name + "_ate.png")).string()};
  writePng(paths[0], top.render(kWidth, kHeight));
  writePng(paths[1], ate.render(kWidth, kHeight * 2 / 3));
  return paths;
}

}  // namespace omnidso::cli
