// Activation of candidates (odometry.hpp, step 5; DSO Sec. 3.2): an immature point whose
// epipolar search has converged (good traces, an interval of at most
// max_activation_interval_px, quality ≥ min_activation_quality) becomes a window point when
// it lands in a free cell of the newest keyframe's occupancy grid (activation_grid.hpp: one
// point per cell of the size that spreads num_points over the image content, smaller while
// the window keeps too few points: activation_density.hpp). The grid is
// the only bound, as DSO's distance map is: a count cap on the window's points had held every
// new point back on forward paths. Each candidate is first refined against every window
// keyframe (new_point_refinement.hpp): unobserved ones wait, inconsistent ones are dropped.
#include <algorithm>
#include <map>
#include <optional>
#include <utility>

#include <omnidso/frontend/activation_density.hpp>
#include <omnidso/frontend/activation_grid.hpp>

#include "odometry_impl.hpp"

namespace omnidso {

// leaving: the keyframes this keyframe step will marginalise. Their points do not occupy a
// cell, and their candidates are not activated: activation refills the window that remains.
// (With N_f = 3 the initial keyframe holds every point when it leaves; had its points kept
// their cells, nothing would have refilled them, and tracking was lost.)
void Odometry::Impl::activatePoints(int newest_id, const std::vector<int>& leaving) {
  const auto is_leaving = [&leaving](int id) {
    return std::find(leaving.begin(), leaving.end(), id) != leaving.end();
  };
  const WindowKeyframe& newest = window->keyframe(newest_id);
  const SE3d T_newest_world = newest.T_world_cam().inverse();
  ActivationGrid grid(camera.width(), camera.height(), content_area, options.num_points,
                      activation_density.update(window->numPoints(), options.num_points));
  for (const auto& [pid, point] : window->points()) {
    if (is_leaving(point->host_id) || !(point->inverse_distance > 0.0)) continue;
    Eigen::Vector2d u;
    if (camera.project(T_newest_world * window->pointInWorld(*point), u)) grid.occupy(u);
  }
  const auto converged = [&](const ImmaturePoint& p) {
    return p.num_good_traces > 0 &&
           (p.last_status == TraceStatus::kGood || p.last_status == TraceStatus::kSkipped) &&
           p.last_interval_px <= options.max_activation_interval_px &&
           p.quality >= options.min_activation_quality && p.inverseDistanceEstimate() > 0.0;
  };
  // Where the candidate would land in the newest keyframe (false: outside its image).
  const auto projectToNewest = [&](int host_id, const ImmaturePoint& p, Eigen::Vector2d* u) {
    const SE3d T_world_host = window->keyframe(host_id).T_world_cam();
    return camera.project(
               T_newest_world * (T_world_host * (p.bearing / p.inverseDistanceEstimate())), *u) &&
           grid.contains(*u);
  };
  const auto refine = [&](int host_id, const ImmaturePoint& p) {
    return window->refineNewPoint(host_id, p.pixel, p.inverseDistanceEstimate(),
                                  options.activation);
  };
  // Every candidate of the keyframes that stay, in the order they are considered.
  struct Entry {
    int host_id;
    int index;
  };
  std::vector<Entry> entries;
  for (const auto& [host_id, list] : immature)
    if (!is_leaving(host_id))
      for (size_t i = 0; i < list.size(); ++i) entries.push_back({host_id, static_cast<int>(i)});
  const auto candidate = [&](const Entry& e) -> ImmaturePoint& {
    return immature.at(e.host_id)[e.index];
  };
  // With compute threads, refinements are computed ahead in batches: from the candidate that
  // needs one, the next kRefinementBatch candidates that could reach that step in the
  // current state are refined in parallel. refineNewPoint reads only the keyframes, which
  // activation does not change, so each result is the one the loop would compute; a
  // candidate whose cell an earlier one of its batch fills, or one past the budget, is
  // refined in vain.
  constexpr size_t kRefinementBatch = 64;
  std::vector<std::optional<NewPointRefinement>> ahead(entries.size());
  const auto refineAhead = [&](size_t from) {
    std::vector<size_t> batch;
    for (size_t e = from; e < entries.size() && batch.size() < kRefinementBatch; ++e) {
      Eigen::Vector2d u;
      const ImmaturePoint& p = candidate(entries[e]);
      if (!converged(p) || (projectToNewest(entries[e].host_id, p, &u) && grid.occupied(u)))
        continue;
      batch.push_back(e);
    }
    pool->run(static_cast<int>(batch.size()), [&](int b) {
      const Entry& e = entries[batch[b]];
      ahead[batch[b]] = refine(e.host_id, candidate(e));
    });
  };
  std::map<int, std::vector<ImmaturePoint>> kept;
  for (size_t e = 0; e < entries.size(); ++e) {
    const int host_id = entries[e].host_id;
    std::vector<ImmaturePoint>& keep = kept[host_id];
    const ImmaturePoint& p = candidate(entries[e]);
    if (!converged(p)) {
      keep.push_back(p);
      continue;
    }
    Eigen::Vector2d u;
    const bool in_newest = projectToNewest(host_id, p, &u);
    if (in_newest && grid.occupied(u)) {
      keep.push_back(p);
      continue;
    }
    double activation_d = p.inverseDistanceEstimate();
    if (options.activation.enabled) {
      if (pool && !ahead[e]) refineAhead(e);
      const NewPointRefinement r = ahead[e] ? *ahead[e] : refine(host_id, p);
      if (r.verdict == NewPointVerdict::kUnobserved) {
        keep.push_back(p);
        continue;
      }
      if (r.verdict == NewPointVerdict::kInconsistent) continue;  // a wrong match: drop
      activation_d = r.inverse_distance;
    }
    if (in_newest) grid.occupy(u);
    window->addPoint(host_id, p.pixel, activation_d);  // < 0: no valid residual, not added
  }
  for (auto& [host_id, list] : kept) immature.at(host_id).swap(list);
}

}  // namespace omnidso
