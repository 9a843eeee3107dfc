#include "omnidso/cameras/calibration/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "omnidso/cameras/calibration/initial_estimate.hpp"
#include "omnidso/cameras/model_fitting.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

constexpr int kMinViews = 4;
constexpr int kScreenIterations = 30;
// ξ values tried along Double Sphere's ξ–focal valley (xiValleyStarts): from below the
// values of real fisheye lenses (≈ −0.2) to beyond the second basin seen here (0.4–0.5).
constexpr double kXiGrid[] = {-0.6, -0.3, 0.0, 0.3, 0.6, 1.0};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

double viewRms(const std::vector<Eigen::Vector2d>& residuals, const std::vector<bool>& used) {
  double sum = 0.0;
  int n = 0;
  for (size_t k = 0; k < residuals.size(); ++k) {
    if (!used[k]) continue;
    sum += residuals[k].allFinite() ? residuals[k].squaredNorm()
                                    : std::numeric_limits<double>::infinity();
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : std::numeric_limits<double>::infinity();
}

// A failed solve keeps its start: reporting that as a calibration would be a silently wrong
// number.
void checkUsable(const BoardAdjustment& fit, const std::string& what) {
  if (!fit.usable)
    throw Error("calibration: the " + what + " adjustment failed: " + fit.solver_message);
}

// Step 3 of the header on the reference residuals.
void dropOutliers(const BoardDetections& detections, const BoardAdjustment& reference,
                  const CalibrationOptions& options, CalibrationReport& report) {
  CornerSelection& s = report.selection;
  std::vector<double> components;
  for (size_t v = 0; v < reference.residuals.size(); ++v)
    for (const Eigen::Vector2d& r : reference.residuals[v])
      if (r.allFinite()) components.insert(components.end(), {std::abs(r.x()), std::abs(r.y())});
  const double sigma = 1.4826 * median(components);
  report.outlier_threshold_px = std::max(options.corner_sigmas * sigma, options.min_outlier_px);
  std::vector<double> view_rms;
  for (size_t v = 0; v < reference.residuals.size(); ++v) {
    for (size_t k = 0; k < reference.residuals[v].size(); ++k) {
      const Eigen::Vector2d& r = reference.residuals[v][k];
      s.corner_used[v][k] = r.allFinite() && r.norm() <= report.outlier_threshold_px;
    }
    view_rms.push_back(viewRms(reference.residuals[v], s.corner_used[v]));
  }
  const double view_threshold =
      std::max(options.view_factor * median(view_rms), options.min_outlier_px);
  for (size_t v = 0; v < view_rms.size(); ++v) {
    const int kept = static_cast<int>(std::count(s.corner_used[v].begin(), s.corner_used[v].end(), true));
    std::ostringstream reason;
    reason.precision(3);
    if (2 * kept < static_cast<int>(s.corner_used[v].size())) {
      reason << detections.views[v].image << ": only " << kept << " of "
             << s.corner_used[v].size() << " corners within " << report.outlier_threshold_px
             << " px";
    } else if (view_rms[v] > view_threshold) {
      reason << detections.views[v].image << ": RMS " << view_rms[v] << " px > "
             << view_threshold << " px (" << options.view_factor << " x the median view)";
    } else {
      report.dropped_corners += static_cast<int>(s.corner_used[v].size()) - kept;
      continue;
    }
    s.view_used[v] = false;
    report.dropped_views.push_back(reason.str());
  }
}

// Starts along Double Sphere's ξ–focal valley. The corners fix the focal length at the
// principal point, f_c = fx / (1 + ξ) (at the axis d1 = 1, k = d2 = 1 + ξ, D = 1 + ξ), but
// ξ and α only weakly, and the cost has separate basins along that valley: on synthetic
// boards (ξ = −0.2) every start converted from the reference ends at ξ = 0.39, fx = 606
// (RMS 0.016 px, not 0), and on the real fisheye photos at ξ = 0.51 (RMS 0.2694 px against
// 0.2692 px at ξ = −0.20). Each start keeps f_c and moves ξ to a grid value; the screen
// (bestStart) then sees every basin the grid reaches. UCM and UCM+radtan have one ξ only:
// every grid start reached the same minimum on those boards, at up to 0.5 s per screen.
std::vector<Camera> xiValleyStarts(const Camera& start) {
  if (start.modelName() != "ds") return {};
  constexpr int kXi = 4;  // [fx, fy, cx, cy, ξ, α]
  const Eigen::VectorXd params = start.params();
  std::vector<Camera> starts;
  for (const double xi : kXiGrid) {
    Eigen::VectorXd p = params;
    p.head<2>() *= (1.0 + xi) / (1.0 + params[kXi]);
    p[kXi] = xi;
    starts.push_back(Camera::create("ds", p, start.width(), start.height()));
  }
  return starts;
}

// Of the starts converted from the reference (each a different local fit of the model to
// the reference over the whole image), the one that fits the corners best with the
// reference's poses held: a cheap screen (no pose updates, a few iterations) before the
// full adjustment, which would otherwise follow whichever basin the first start lies in.
Camera bestStart(const BoardDetections& detections, const BoardSpec& board,
                 const CornerSelection& selection, const BoardAdjustment& reference,
                 const std::vector<Camera>& starts) {
  if (starts.size() == 1) return starts.front();
  AdjustmentOptions screen;
  screen.fix_poses = true;
  screen.max_iterations = kScreenIterations;
  screen.compute_covariance = false;
  size_t best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<Camera> screened;
  for (size_t i = 0; i < starts.size(); ++i) {
    const BoardAdjustment fit =
        adjustBoards(detections, board, selection, starts[i], reference.T_camera_board, screen);
    screened.push_back(fit.camera);
    if (fit.usable && fit.sum_squared_px < best_cost) best_cost = fit.sum_squared_px, best = i;
  }
  return screened[best];
}

}  // namespace

std::vector<std::string> parseModelList(const std::string& comma_separated) {
  std::vector<std::string> models;
  std::stringstream in(comma_separated);
  std::string item;
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) continue;
    const std::string name = canonicalCameraModelName(item);
    if (std::find(models.begin(), models.end(), name) != models.end())
      throw Error("--models: '" + item + "' names " + name + " a second time");
    models.push_back(name);
  }
  if (models.empty()) throw Error("--models: no model given");
  return models;
}

ModelCalibration summariseFit(BoardAdjustment fit, const CornerSelection& selection) {
  ModelCalibration m{std::move(fit)};
  const int n = selection.numCorners();
  const Camera& camera = m.fit.camera;
  for (size_t v = 0; v < m.fit.residuals.size(); ++v) {
    if (!selection.view_used[v]) {
      m.view_rms_px.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const std::vector<Eigen::Vector2d>& residuals = m.fit.residuals[v];
    m.view_rms_px.push_back(viewRms(residuals, selection.corner_used[v]));
    for (size_t k = 0; k < residuals.size(); ++k)
      if (selection.corner_used[v][k])
        m.max_px = std::max(m.max_px, residuals[k].allFinite()
                                          ? residuals[k].norm()
                                          : std::numeric_limits<double>::infinity());
  }
  m.rms_px = n > 0 ? std::sqrt(m.fit.sum_squared_px / n) : 0.0;
  m.num_params = static_cast<int>(camera.params().size());
  const double num_residuals = 2.0 * n;
  m.bic = num_residuals * std::log(std::max(m.fit.sum_squared_px, 1e-300) / num_residuals) +
          m.num_params * std::log(num_residuals);
  m.fov = fieldOfView(camera);
  return m;
}

CalibrationReport calibrateModels(const BoardDetections& detections, const BoardSpec& board,
                                  const std::vector<std::string>& models,
                                  const CalibrationOptions& options) {
  CalibrationReport report;
  report.selection = CornerSelection::all(detections);
  const auto tooFew = [&](const std::string& when) {
    return Error("calibration: " + std::to_string(report.selection.numViews()) +
                 " usable views " + when + "; at least " + std::to_string(kMinViews) +
                 " are needed (images without a board: " +
                 std::to_string(detections.without_board.size()) + ")");
  };
  if (report.selection.numViews() < kMinViews) throw tooFew("show the board");

  const InitialCalibration start = initialEquidistantCalibration(detections, board);
  AdjustmentOptions reference_options = options.adjustment;
  reference_options.compute_covariance = false;
  BoardAdjustment reference = adjustBoards(detections, board, report.selection, start.camera,
                                           start.T_camera_board, reference_options);
  checkUsable(reference, "kb4 reference");
  dropOutliers(detections, reference, options, report);
  if (report.selection.numViews() < kMinViews) throw tooFew("remain after dropping outliers");
  reference = adjustBoards(detections, board, report.selection, reference.camera,
                           reference.T_camera_board, options.adjustment);
  checkUsable(reference, "kb4 reference");

  FitOptions conversion;
  conversion.samples_per_axis = 24;
  conversion.validation_per_axis = 24;
  conversion.boundary_samples = 90;
  for (const std::string& name : models) {
    BoardAdjustment fit = reference;
    if (name != "kb4") {
      std::vector<Camera> starts = fitCameraModelStarts(reference.camera, name, conversion);
      const std::vector<Camera> valley = xiValleyStarts(starts.front());
      starts.insert(starts.end(), valley.begin(), valley.end());
      fit = adjustBoards(detections, board, report.selection,
                         bestStart(detections, board, report.selection, reference, starts),
                         reference.T_camera_board, options.adjustment);
    }
    checkUsable(fit, name);
    report.models.push_back(summariseFit(std::move(fit), report.selection));
  }
  for (size_t i = 1; i < report.models.size(); ++i)
    if (report.models[i].bic < report.models[report.selected].bic) report.selected = i;
  return report;
}

}  // namespace omnidso
