// SlidingWindow's marginalisation step (sliding_window.hpp, paper Sec. V-C): the policy's
// view of the window, then for a keyframe leaving it — its points and the points the two
// newest keyframes no longer observe are marginalised into the prior (kept for the map as
// MarginalizedPoint; natively where their residual blocks are deferred,
// window_point_marginalization.hpp) — those with fewer than
// WindowOptions::min_residuals_to_marginalize residuals are dropped instead, neither in the
// prior nor in the map —, the other points' residuals into it are dropped (DSO:
// sparsity), and finally its own pose and affine blocks are marginalised (marginalizer.hpp).
#include <algorithm>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/backend/window_point_marginalization.hpp>

namespace omnidso {

std::vector<MarginalizedPoint> SlidingWindow::takeMarginalizedPoints() {
  std::vector<MarginalizedPoint> out;
  out.swap(marginalized_points_);
  return out;
}

void SlidingWindow::recordMarginalized(const WindowPoint& point) {
  if (!(point.inverse_distance > 0.0)) return;  // at infinity: no position to keep
  Eigen::Vector3d bearing;
  if (!factory_->unproject(intrinsics_, point.pixel, bearing)) return;
  MarginalizedPoint m;
  m.position_world = keyframe(point.host_id).T_world_cam() * (bearing / point.inverse_distance);
  m.intensity = point.hostIntensity();
  marginalized_points_.push_back(m);
}

std::vector<KeyframeSummary> SlidingWindow::keyframeSummaries() const {
  std::vector<KeyframeSummary> out;
  if (keyframes_.empty()) return out;
  const int newest = keyframes_.back()->id;
  std::map<int, KeyframeSummary> by_id;
  for (const auto& kf : keyframes_) {
    KeyframeSummary s;
    s.id = kf->id;
    s.T_world_cam = kf->T_world_cam();
    by_id[kf->id] = s;
  }
  for (const auto& [pid, point] : points_) {
    KeyframeSummary& s = by_id[point->host_id];
    ++s.num_points;
    if (point->host_id == newest || point->residuals.count(newest)) ++s.num_points_visible_in_newest;
  }
  for (const auto& kf : keyframes_) out.push_back(by_id[kf->id]);
  return out;
}

std::vector<int> SlidingWindow::keyframesToMarginalize(
    const KeyframeMarginalizationOptions& policy) const {
  KeyframeMarginalizationOptions o = policy;
  o.max_keyframes = options_.max_keyframes;
  return selectKeyframesToMarginalize(keyframeSummaries(), o);
}

bool SlidingWindow::marginalizePointsNatively(const std::vector<int>& ids) {
  if (!defersResidualBlocks(0)) return false;
  std::vector<const WindowPoint*> points;
  std::vector<ceres::ResidualBlockId> blocks;
  for (int pid : ids) {
    const WindowPoint& point = pointRef(pid);
    for (const auto& [target, block] : point.residuals)
      if (block) return false;
    problem_->GetResidualBlocksForParameterBlock(&point.inverse_distance, &blocks);
    if (!blocks.empty()) return false;
    points.push_back(&point);
  }
  const WindowProblem current = nativePhotometricProblem(points);
  // The same problem with the frames' and intrinsics' values at their first estimate x̄.
  const std::optional<WindowProblem> first_estimate = firstEstimateProblem(current);
  // The image gradient at x as in the solve (DSO); without first-estimate Jacobians in the
  // solve, at x̄ with the rest of the Jacobian, as Ceres's marginaliser takes it — the native
  // path then reproduces the Ceres path, its oracle (WindowSolverAgainstCeres).
  const PointSchurComplement schur = marginalizePoints(
      current, first_estimate ? *first_estimate : current,
      options_.first_estimate_jacobians ? WindowPhotometricTerms::ImageGradientAt::kCurrentEstimate
                                        : WindowPhotometricTerms::ImageGradientAt::kFirstEstimate);
  if (marginalizer_.addPrior(*problem_, schur.blocks, schur.information, schur.gradient))
    has_prior_ = true;
  for (const WindowPoint* point : points) {
    problem_->RemoveParameterBlock(&point->inverse_distance);
    marginalizer_.forget(&point->inverse_distance);
  }
  return true;
}

void SlidingWindow::marginalizeKeyframe(int id) {
  WindowKeyframe& kf = keyframeRef(id);
  std::vector<int> newest_two;
  for (size_t i = keyframes_.size(); i-- > 0 && newest_two.size() < 2;)
    if (keyframes_[i]->id != id) newest_two.push_back(keyframes_[i]->id);

  // 1. Points hosted by the keyframe, or no longer observed by the two newest keyframes.
  const size_t min_residuals = std::max(1, options_.min_residuals_to_marginalize);
  std::vector<double*> to_marginalize;
  std::vector<int> marginalized_ids, dropped_ids;
  for (const auto& [pid, point] : points_) {
    bool observed_by_newest = false;
    for (int n : newest_two)
      observed_by_newest |= point->host_id == n || point->residuals.count(n) > 0;
    if (point->host_id != id && observed_by_newest) continue;
    if (point->residuals.size() < min_residuals) {
      dropped_ids.push_back(pid);
    } else {
      to_marginalize.push_back(&point->inverse_distance);
      marginalized_ids.push_back(pid);
      recordMarginalized(*point);
    }
  }
  // Natively where the points' blocks are deferred; else Ceres's linearisation, for which
  // their deferred blocks (if any) enter the problem.
  if (!to_marginalize.empty() && !marginalizePointsNatively(marginalized_ids)) {
    for (int pid : marginalized_ids) materializeResidualBlocks(pointRef(pid));
    if (marginalizer_.marginalize(*problem_, to_marginalize)) has_prior_ = true;
  }
  for (int pid : marginalized_ids) {
    if (pid == scale_anchor_point_id_) {
      scale_fixed_by_prior_ = !options_.keep_scale_anchor;
      scale_anchor_point_id_ = -1;
    }
    erasePoint(pid);
  }
  for (int pid : dropped_ids) dropPoint(pid);

  // 2. Residuals of the remaining points into this keyframe are dropped (sparsity).
  std::vector<int> emptied;
  for (auto& [pid, point] : points_) {
    const auto it = point->residuals.find(id);
    if (it == point->residuals.end()) continue;
    removeResidualBlock(it->second);
    point->residuals.erase(it);
    if (point->residuals.empty()) emptied.push_back(pid);
  }
  for (int pid : emptied) dropPoint(pid);

  // 3. The keyframe's own blocks. No photometric residual touches them any more (1 and 2),
  // deferred or not: the marginaliser finds the priors on them in the problem.
  if (marginalizer_.marginalize(*problem_, {kf.pose.data(), kf.affine.data()})) has_prior_ = true;
  if (id == anchor_keyframe_id_) anchor_keyframe_id_ = -1;
  keyframes_.erase(std::find_if(keyframes_.begin(), keyframes_.end(),
                                [id](const auto& k) { return k->id == id; }));
}

}  // namespace omnidso
