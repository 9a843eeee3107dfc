#include <algorithm>
#include <cmath>
#include <utility>
#include <omnidso/core/error.hpp>
#include <omnidso/core/scale_drift.hpp>

namespace omnidso {
namespace {

// Slope of the least-squares line y ≈ α + β x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  const double denominator = n * sxx - sx * sx;
  return denominator > 0.0 ? (n * sxy - sx * sy) / denominator : 0.0;
}

constexpr double kMinDefaultWindowM = 0.5;

// The samples σ_k at window Δ, and how many pairs had a window ahead of them.
ScaleDrift localScales(const Trajectory& gt, const Trajectory& est,
                       const EvaluationResult& result, double window_m) {
  if (!(window_m > 0.0) || !std::isfinite(window_m))
    throw Error("scale drift: the window must be a positive length (got " +
                std::to_string(window_m) + " m)");
  const Association& pairs = result.association;
  const double s = result.alignment.scale();
  // Ground-truth path length at every associated pair.
  std::vector<double> along(pairs.size(), 0.0);
  for (size_t k = 1; k < pairs.size(); ++k)
    along[k] = along[k - 1] +
               (gt[pairs[k].first].pose.translation() - gt[pairs[k - 1].first].pose.translation()).norm();
  ScaleDrift drift;
  drift.window_m = window_m;
  size_t j = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    j = std::max(j, k + 1);
    while (j < pairs.size() && along[j] - along[k] < window_m) ++j;
    if (j >= pairs.size()) break;
    ++drift.pairs_with_window;
    const double chord_gt =
        (gt[pairs[j].first].pose.translation() - gt[pairs[k].first].pose.translation()).norm();
    if (chord_gt < 0.5 * window_m) continue;
    const double chord_est =
        (est[pairs[j].second].pose.translation() - est[pairs[k].second].pose.translation()).norm();
    if (!(chord_est > 0.0)) continue;  // log σ undefined: a collapsed estimate
    drift.samples.push_back({along[k], gt[pairs[k].first].timestamp - gt[pairs.front().first].timestamp,
                             s * chord_est / chord_gt});
  }
  return drift;
}

// The trend of log σ (header), or nothing with fewer than three samples.
std::optional<ScaleDrift> fitTrend(ScaleDrift drift, const EvaluationResult& result) {
  if (drift.samples.size() < 3) return std::nullopt;
  std::vector<double> distance, time, log_ratio;
  drift.min_ratio = drift.max_ratio = drift.samples.front().ratio;
  for (const LocalScale& sample : drift.samples) {
    distance.push_back(sample.distance_m);
    time.push_back(sample.time_s);
    log_ratio.push_back(std::log(sample.ratio));
    drift.min_ratio = std::min(drift.min_ratio, sample.ratio);
    drift.max_ratio = std::max(drift.max_ratio, sample.ratio);
  }
  const double per_metre = slope(distance, log_ratio);
  const double per_second = slope(time, log_ratio);
  drift.percent_per_10m = 100.0 * std::expm1(10.0 * per_metre);
  drift.percent_per_minute = 100.0 * std::expm1(60.0 * per_second);
  drift.percent_over_sequence = 100.0 * std::expm1(per_metre * result.gt_length_m);
  return drift;
}

}  // namespace

double defaultScaleDriftWindow(double gt_length_m) {
  return std::max(kMinDefaultWindowM, 0.1 * gt_length_m);
}

std::optional<ScaleDrift> computeScaleDrift(const Trajectory& gt, const Trajectory& est,
                                            const EvaluationResult& result, double window_m) {
  return fitTrend(localScales(gt, est, result, window_m), result);
}

std::optional<ScaleDrift> computeScaleDriftDefaultWindow(const Trajectory& gt,
                                                         const Trajectory& est,
                                                         const EvaluationResult& result) {
  double window = defaultScaleDriftWindow(result.gt_length_m);
  ScaleDrift drift = localScales(gt, est, result, window);
  while (2 * drift.samples.size() < static_cast<size_t>(drift.pairs_with_window) &&
         0.5 * window >= kMinDefaultWindowM) {
    window *= 0.5;
    drift = localScales(gt, est, result, window);
  }
  return fitTrend(std::move(drift), result);
}

}  // namespace omnidso
