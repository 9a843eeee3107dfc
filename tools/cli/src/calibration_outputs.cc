#include <fmt/core.h>

#include <cmath>
#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cli/calibration_outputs.hpp>
#include <omnidso/cli/text_table.hpp>

namespace omnidso::cli {
namespace {

using Json = nlohmann::ordered_json;

Json nullIfNan(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

Json modelJson(const ModelCalibration& m, const CalibrationRun& run) {
  const Camera& camera = m.fit.camera;
  const Eigen::VectorXd values = camera.params();
  const std::vector<std::string> names = camera.paramNames();
  Json params = Json::object();
  for (size_t i = 0; i < names.size(); ++i) {
    const int j = static_cast<int>(i);
    params[names[i]] = {{"value", values[j]},
                        {"stddev", m.fit.param_stddev.size() > j ? Json(m.fit.param_stddev[j])
                                                                 : Json(nullptr)}};
  }
  Json views = Json::array();
  for (size_t v = 0; v < m.view_rms_px.size(); ++v)
    views.push_back({{"image", run.detections.views[v].image},
                     {"rms_px", nullIfNan(m.view_rms_px[v])}});
  return Json{{"model", camera.modelName()},
              {"num_params", m.num_params},
              {"parameters", params},
              {"rms_px", m.rms_px},
              {"max_px", m.max_px},
              {"noise_sigma_px", m.fit.noise_sigma_px},
              {"bic", m.bic},
              {"num_views", run.report.selection.numViews()},
              {"num_corners", run.report.selection.numCorners()},
              {"iterations", m.fit.iterations},
              {"converged", m.fit.converged},
              {"fov_deg",
               {{"horizontal", m.fov.horizontal_deg},
                {"vertical", m.fov.vertical_deg},
                {"diagonal", m.fov.diagonal_deg},
                {"maximum", m.fov.maximum_deg}}},
              {"per_view", views}};
}

// The detected corners of every view with a board, and which of them the models were fitted
// to, so that another calibrator can be run on exactly the same corners.
Json detectionsJson(const CalibrationRun& run) {
  Json views = Json::array();
  for (size_t v = 0; v < run.detections.views.size(); ++v) {
    Json corners = Json::array();
    for (const Eigen::Vector2d& c : run.detections.views[v].corners)
      corners.push_back({c.x(), c.y()});
    views.push_back({{"image", run.detections.views[v].image},
                     {"used", static_cast<bool>(run.report.selection.view_used[v])},
                     {"corners", corners},
                     {"corner_used", run.report.selection.corner_used[v]}});
  }
  return views;
}

std::string fmtNumber(double x, int digits) {
  return std::isfinite(x) ? fmt::format("{:.{}f}", x, digits) : "-";
}

}  // namespace

Json calibrationJson(const CalibrationRun& run) {
  const CalibrationReport& r = run.report;
  Json models = Json::array();
  for (const ModelCalibration& m : r.models) models.push_back(modelJson(m, run));
  return Json{{"images", run.images_dir},
              {"board", {{"cols", run.board.cols}, {"rows", run.board.rows},
                         {"square_m", run.board.square}}},
              {"image_size", {run.detections.width, run.detections.height}},
              {"images_without_board", run.detections.without_board},
              {"dropped_views", r.dropped_views},
              {"dropped_corners", r.dropped_corners},
              {"outlier_threshold_px", r.outlier_threshold_px},
              {"selected", r.models[run.chosen].fit.camera.modelName()},
              {"selection", run.chosen_by_user ? "--select" : "lowest BIC"},
              {"models", models},
              {"detections", detectionsJson(run)}};
}

std::string comparisonMarkdown(const CalibrationRun& run) {
  const CalibrationReport& r = run.report;
  double best_bic = r.models[r.selected].bic;
  TextTable table;
  table.header = {"model", "params", "views", "corners", "RMS [px]", "max [px]", "BIC",
                  "ΔBIC", "FOV h [°]", "FOV v [°]", "FOV diag [°]", "camera.txt"};
  for (const ModelCalibration& m : r.models) {
    const std::string name = m.fit.camera.modelName();
    table.rows.push_back({name + (&m == &r.models[run.chosen] ? " (selected)" : ""),
                          std::to_string(m.num_params),
                          std::to_string(r.selection.numViews()),
                          std::to_string(r.selection.numCorners()), fmtNumber(m.rms_px, 4),
                          fmtNumber(m.max_px, 3), fmtNumber(m.bic, 1),
                          fmtNumber(m.bic - best_bic, 1), fmtNumber(m.fov.horizontal_deg, 1),
                          fmtNumber(m.fov.vertical_deg, 1), fmtNumber(m.fov.diagonal_deg, 1),
                          dsoCameraTxtKeyword(name).empty() ? "no" : "yes"});
  }
  std::string out = fmt::format(
      "# Calibration of {} ({}x{} board, {} x {} px)\n\n", run.images_dir, run.board.cols,
      run.board.rows, run.detections.width, run.detections.height);
  out += markdownTable(table);
  out += fmt::format(
      "\nSelected: **{}** ({}). BIC = m ln(RSS/m) + k ln(m), m = 2 x corners, k = intrinsic "
      "parameters; lower is better.\n",
      r.models[run.chosen].fit.camera.modelName(),
      run.chosen_by_user ? "--select" : "lowest BIC");
  out += fmt::format("\nOutliers: {} corners beyond {:.3f} px dropped; {} views dropped; {} "
                     "images without a board.\n",
                     r.dropped_corners, r.outlier_threshold_px, r.dropped_views.size(),
                     run.detections.without_board.size());
  for (const std::string& v : r.dropped_views) out += "- " + v + "\n";
  for (const ModelCalibration& m : r.models)
    if (!m.fit.converged)
      out += fmt::format("\nNot converged: {} stopped after {} iterations ({}).\n",
                         m.fit.camera.modelName(), m.fit.iterations, m.fit.solver_message);
  for (const ModelCalibration& m : r.models) {
    TextTable params;
    params.header = {"parameter", "value", "std dev"};
    const Eigen::VectorXd values = m.fit.camera.params();
    const std::vector<std::string> names = m.fit.camera.paramNames();
    for (size_t i = 0; i < names.size(); ++i) {
      const int j = static_cast<int>(i);
      params.rows.push_back({names[i], fmt::format("{:.8g}", values[j]),
                             m.fit.param_stddev.size() > j
                                 ? fmt::format("{:.3g}", m.fit.param_stddev[j])
                                 : "-"});
    }
    out += "\n## " + m.fit.camera.modelName() + "\n\n" + markdownTable(params);
  }
  return out;
}

}  // namespace omnidso::cli
