// Activation of candidates (odometry.hpp, step 5; DSO Sec. 3.2): an immature point whose
// epipolar search has converged (good traces, an interval of at most
// max_activation_interval_px, quality ≥ min_activation_quality) becomes a window point while
// the window that remains after this keyframe step holds fewer than num_points. An occupancy
// grid in the newest keyframe, one point per cell of the size that spreads num_points over
// the image content, keeps the map spread out; each candidate is first refined against every
// window keyframe (new_point_refinement.hpp): unobserved ones wait, inconsistent ones are
// dropped.
#include <algorithm>
#include <cmath>

#include "odometry_impl.hpp"

namespace omnidso {

// leaving: the keyframes this keyframe step will marginalise. Their points neither count
// against num_points nor occupy a cell, and their candidates are not activated: activation
// refills the window that remains. (With N_f = 3 the initial keyframe holds every point when
// it leaves; counting its points left the window empty and tracking lost.)
void Odometry::Impl::activatePoints(int newest_id, const std::vector<int>& leaving) {
  const auto is_leaving = [&leaving](int id) {
    return std::find(leaving.begin(), leaving.end(), id) != leaving.end();
  };
  const WindowKeyframe& newest = window->keyframe(newest_id);
  const SE3d T_newest_world = newest.T_world_cam().inverse();
  // Occupancy grid in the newest keyframe: one point per cell keeps the map spread out.
  const double valid_area = std::max(1.0, static_cast<double>(std::count_if(
      mask.data(), mask.data() + mask.size(), [](std::uint8_t m) { return m != 0; })));
  const double cell = std::max(2.0, std::sqrt(valid_area / std::max(1, options.num_points)));
  const int gw = static_cast<int>(camera.width() / cell) + 1;
  const int gh = static_cast<int>(camera.height() / cell) + 1;
  std::vector<char> occupied(static_cast<size_t>(gw) * gh, 0);
  auto cellOf = [&](const Eigen::Vector2d& u) {
    return static_cast<size_t>(static_cast<int>(u.y() / cell)) * gw +
           static_cast<size_t>(static_cast<int>(u.x() / cell));
  };
  int num_staying = 0;
  for (const auto& [pid, point] : window->points()) {
    if (is_leaving(point->host_id)) continue;
    ++num_staying;
    if (!(point->inverse_distance > 0.0)) continue;
    Eigen::Vector2d u;
    if (camera.project(T_newest_world * window->pointInWorld(*point), u)) occupied[cellOf(u)] = 1;
  }
  for (auto& [host_id, list] : immature) {
    if (is_leaving(host_id)) continue;
    const SE3d T_world_host = window->keyframe(host_id).T_world_cam();
    std::vector<ImmaturePoint> keep;
    for (ImmaturePoint& p : list) {
      const bool converged = p.num_good_traces > 0 &&
                             (p.last_status == TraceStatus::kGood ||
                              p.last_status == TraceStatus::kSkipped) &&
                             p.last_interval_px <= options.max_activation_interval_px &&
                             p.quality >= options.min_activation_quality;
      const double d = p.inverseDistanceEstimate();
      if (!converged || num_staying >= options.num_points || !(d > 0.0)) {
        keep.push_back(p);
        continue;
      }
      Eigen::Vector2d u;
      const Eigen::Vector3d x = T_newest_world * (T_world_host * (p.bearing / d));
      const bool in_newest = camera.project(x, u);
      if (in_newest && occupied[cellOf(u)]) {
        keep.push_back(p);
        continue;
      }
      double activation_d = d;
      if (options.activation.enabled) {
        const NewPointRefinement r =
            window->refineNewPoint(host_id, p.pixel, d, options.activation);
        if (r.verdict == NewPointVerdict::kUnobserved) {
          keep.push_back(p);
          continue;
        }
        if (r.verdict == NewPointVerdict::kInconsistent) continue;  // a wrong match: drop
        activation_d = r.inverse_distance;
      }
      if (in_newest) occupied[cellOf(u)] = 1;
      if (window->addPoint(host_id, p.pixel, activation_d) < 0) continue;  // no valid residual
      ++num_staying;
    }
    list.swap(keep);
  }
}

}  // namespace omnidso
