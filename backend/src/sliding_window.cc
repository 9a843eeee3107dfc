#include <ceres/loss_function.h>
#include <ceres/ordered_groups.h>
#include <ceres/solver.h>

#include <algorithm>
#include <omnidso/backend/affine_prior.hpp>
#include <omnidso/backend/intrinsics_prior.hpp>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <omnidso/residuals/residual_pattern.hpp>
#include <omnidso/residuals/reusing_cost_function.hpp>
#include <omnidso/residuals/se3_manifold.hpp>

namespace omnidso {

bool hostPatchFits(const ImageF& image, const Eigen::Vector2d& pixel) {
  const double margin = patternRadius<kWindowPatternSize>() + 1.0;
  return pixel.x() >= margin && pixel.y() >= margin && pixel.x() <= image.width() - 1 - margin &&
         pixel.y() <= image.height() - 1 - margin;
}

SlidingWindow::SlidingWindow(const std::string& model_name, const Eigen::VectorXd& intrinsics,
                             WindowOptions options)
    : options_(options),
      factory_(PhotometricResidualFactory::forModel(model_name)),
      intrinsics_(intrinsics),
      pose_manifold_(std::make_unique<SE3Manifold>()),
      loss_(makePhotometricLoss(kWindowPatternSize, options.huber_threshold)),
      inverse_distance_slots_(options.max_points) {
  if (intrinsics_.size() != factory_->numIntrinsics())
    throw Error("SlidingWindow: model '" + model_name + "' takes " +
                std::to_string(factory_->numIntrinsics()) + " intrinsics, got " +
                std::to_string(intrinsics_.size()));
  if (options_.max_keyframes < 2) throw Error("SlidingWindow: max_keyframes must be at least 2");
  ceres::Problem::Options problem_options;
  problem_options.enable_fast_removal = true;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  if (options_.reuse_evaluations) problem_options.evaluation_callback = &evaluation_reuse_;
  problem_ = std::make_unique<ceres::Problem>(problem_options);
  problem_->AddParameterBlock(intrinsics_.data(), static_cast<int>(intrinsics_.size()));
  if (!options_.optimize_intrinsics) problem_->SetParameterBlockConstant(intrinsics_.data());
  else if (options_.intrinsics_prior_weight > 0)
    problem_->AddResidualBlock(new IntrinsicsPrior(intrinsics_, options_.intrinsics_prior_weight),
                               nullptr, intrinsics_.data());
}

SlidingWindow::~SlidingWindow() = default;

std::vector<int> SlidingWindow::keyframeIds() const {
  std::vector<int> ids;
  for (const auto& kf : keyframes_) ids.push_back(kf->id);
  return ids;
}

const WindowKeyframe& SlidingWindow::keyframe(int id) const {
  for (const auto& kf : keyframes_)
    if (kf->id == id) return *kf;
  throw Error("SlidingWindow: no keyframe " + std::to_string(id) + " in the window");
}

WindowKeyframe& SlidingWindow::keyframeRef(int id) {
  return const_cast<WindowKeyframe&>(static_cast<const SlidingWindow&>(*this).keyframe(id));
}

WindowPoint& SlidingWindow::pointRef(int id) {
  const auto it = points_.find(id);
  if (it == points_.end()) throw Error("SlidingWindow: no point " + std::to_string(id));
  return *it->second;
}

WindowKeyframe& SlidingWindow::mutableKeyframe(int id) {
  all_residuals_valid_ = false;  // the caller may move it
  return keyframeRef(id);
}

WindowPoint& SlidingWindow::mutablePoint(int id) {
  all_residuals_valid_ = false;
  return pointRef(id);
}

Eigen::VectorXd& SlidingWindow::mutableIntrinsics() {
  all_residuals_valid_ = false;
  return intrinsics_;
}

int SlidingWindow::numResiduals() const {
  int n = 0;
  for (const auto& [id, point] : points_) n += static_cast<int>(point->residuals.size());
  return n;
}

void SlidingWindow::addKeyframe(int id, double timestamp, double exposure,
                                const SE3d& T_world_cam, const Eigen::Vector2d& affine,
                                std::shared_ptr<const ImagePyramid> pyramid) {
  for (const auto& kf : keyframes_)
    if (kf->id == id) throw Error("SlidingWindow: keyframe " + std::to_string(id) + " added twice");
  if (!pyramid) throw Error("SlidingWindow: keyframe " + std::to_string(id) + " has no image");
  auto kf = std::make_unique<WindowKeyframe>();
  kf->id = id;
  kf->timestamp = timestamp;
  kf->exposure = exposure;
  T_world_cam.toParameters(kf->pose.data());
  kf->affine = {affine.x(), affine.y()};
  kf->pyramid = std::move(pyramid);
  problem_->AddParameterBlock(kf->pose.data(), 7, pose_manifold_.get());
  problem_->AddParameterBlock(kf->affine.data(), 2);
  if (options_.affine_prior_weight_a > 0 || options_.affine_prior_weight_b > 0)
    problem_->AddResidualBlock(new AffinePrior(Eigen::Vector2d::Zero(), options_.affine_prior_weight_a,
                                               options_.affine_prior_weight_b),
                               nullptr, kf->affine.data());
  if (anchor_keyframe_id_ < 0 && !has_prior_) {
    anchor_keyframe_id_ = id;  // gauge: pose and brightness offset
    problem_->SetParameterBlockConstant(kf->pose.data());
    problem_->SetParameterBlockConstant(kf->affine.data());
  }
  WindowKeyframe& target = *kf;
  keyframes_.push_back(std::move(kf));
  for (auto& [pid, point] : points_)
    if (point->host_id != id) addResidual(*point, target);
}

std::optional<WindowObservation> SlidingWindow::observation(const WindowPoint& point,
                                                           const WindowKeyframe& target,
                                                           int level) const {
  const WindowKeyframe& host = keyframe(point.host_id);
  WindowObservation obs;
  if (level == 0) {
    obs.host = point.patch;
  } else {
    // The host patch on level L: the level-0 pixel mapped by pyramid_scaling.hpp.
    const ImageF& image = host.pyramid->level(level);
    const Eigen::Vector2d pixel(pixelToLevel(point.pixel.x(), level),
                                pixelToLevel(point.pixel.y(), level));
    if (!hostPatchFits(image, pixel)) return std::nullopt;
    obs.host = makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(level), pixel,
                                                 options_.gradient_weight_c);
  }
  obs.target_image = &target.pyramid->level(level);
  obs.host_exposure = host.exposure;
  obs.target_exposure = target.exposure;
  obs.level = level;
  return obs;
}

bool SlidingWindow::addResidual(WindowPoint& point, WindowKeyframe& target, int level) {
  WindowKeyframe& host = keyframeRef(point.host_id);
  const std::optional<WindowObservation> maybe_obs = observation(point, target, level);
  if (!maybe_obs) return false;
  const WindowObservation& obs = *maybe_obs;
  std::vector<double*> blocks = {host.pose.data(),   target.pose.data(),  &point.inverse_distance,
                                 host.affine.data(), target.affine.data(), intrinsics_.data()};
  if (factory_->status(obs, blocks.data()) != PhotometricStatus::kValid) return false;
  ceres::CostFunction* cost = factory_->makeCost(options_.differentiation, obs);
  if (options_.reuse_evaluations) cost = new ReusingCostFunction(cost, &evaluation_reuse_);
  point.residuals[target.id] = problem_->AddResidualBlock(
      new OutOfBoundsPenalty(cost, options_.outlier_energy_per_pixel * kWindowPatternSize),
      loss_.get(), blocks);
  return true;
}

int SlidingWindow::addPoint(int host_id, const Eigen::Vector2d& pixel, double inverse_distance) {
  const WindowKeyframe& host = keyframe(host_id);
  const ImageF& image = host.pyramid->level(0);
  if (!hostPatchFits(image, pixel)) return -1;
  auto point = std::make_unique<WindowPoint>(*inverse_distance_slots_.acquire());
  point->id = next_point_id_;
  point->host_id = host_id;
  point->pixel = pixel;
  point->inverse_distance = inverse_distance;
  point->patch = makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(0), pixel,
                                                   options_.gradient_weight_c);
  problem_->AddParameterBlock(&point->inverse_distance, 1);
  for (auto& kf : keyframes_)
    if (kf->id != host_id) addResidual(*point, *kf);
  if (point->residuals.empty()) {
    problem_->RemoveParameterBlock(&point->inverse_distance);
    inverse_distance_slots_.release(&point->inverse_distance);
    return -1;
  }
  ++next_point_id_;
  const int id = point->id;
  points_.emplace(id, std::move(point));
  return id;
}

void SlidingWindow::fixGaugeBeforeFirstSolve() {
  if (scale_anchor_point_id_ >= 0 || scale_fixed_by_prior_ || points_.empty()) return;
  // The point with the most residuals, preferring the pose anchor's own points; ties go to
  // the lowest id, so the choice is deterministic.
  const WindowPoint* best = nullptr;
  for (const auto& [id, point] : points_) {
    if (!best) {
      best = point.get();
      continue;
    }
    const bool point_anchored = point->host_id == anchor_keyframe_id_;
    const bool best_anchored = best->host_id == anchor_keyframe_id_;
    if (point_anchored != best_anchored) {
      if (point_anchored) best = point.get();
      continue;
    }
    if (point->residuals.size() > best->residuals.size()) best = point.get();
  }
  scale_anchor_point_id_ = best->id;
  problem_->SetParameterBlockConstant(&pointRef(best->id).inverse_distance);
}

int SlidingWindow::removeResiduals(double max_energy, int min_residuals_per_point) {
  int removed = 0;
  std::vector<int> weak_points;
  for (auto& [pid, point] : points_) {
    for (auto it = point->residuals.begin(); it != point->residuals.end();) {
      // Every photometric block of the window is an OutOfBoundsPenalty (addResidual).
      if (rawEnergy(*problem_, it->second) <= max_energy) {
        ++it;
        continue;
      }
      problem_->RemoveResidualBlock(it->second);
      it = point->residuals.erase(it);
      ++removed;
    }
    if (static_cast<int>(point->residuals.size()) < min_residuals_per_point)
      weak_points.push_back(pid);
  }
  for (int pid : weak_points) removePoint(pid, false);
  all_residuals_valid_ = true;  // every invalid one had infinite energy
  return removed;
}

int SlidingWindow::dropInvalidResiduals() {
  return removeResiduals(std::numeric_limits<double>::max(), 1);
}

WindowSolveSummary SlidingWindow::optimize() {
  // Residuals whose projection has left the image (or the model's domain) since they were
  // made would only carry the constant penalty: dropped, as DSO drops out-of-bounds residuals.
  // Skipped when nothing has moved since the last pass (the odometry's removeOutliers after
  // the previous solve; new residuals are only added where valid).
  if (!all_residuals_valid_) dropInvalidResiduals();
  fixGaugeBeforeFirstSolve();
  return solve();
}

void SlidingWindow::rebuildResiduals(int level,
                                     const std::map<int, std::vector<int>>& targets_by_point) {
  for (auto& [pid, point] : points_) {
    for (const auto& [target, id] : point->residuals) problem_->RemoveResidualBlock(id);
    point->residuals.clear();
    for (int target : targets_by_point.at(pid)) addResidual(*point, keyframeRef(target), level);
  }
}

WindowSolveSummary SlidingWindow::optimizeCoarseToFine(int num_levels) {
  dropInvalidResiduals();
  fixGaugeBeforeFirstSolve();
  std::map<int, std::vector<int>> targets;
  for (const auto& [pid, point] : points_)
    for (const auto& [target, id] : point->residuals) targets[pid].push_back(target);
  const int coarsest = std::min(num_levels, keyframes_.front()->pyramid->numLevels()) - 1;
  WindowSolveSummary total;
  total.initial_cost = std::numeric_limits<double>::quiet_NaN();
  for (int level = coarsest; level >= 0; --level) {
    rebuildResiduals(level, targets);
    const WindowSolveSummary s = solve();
    if (level == coarsest) total.initial_cost = s.initial_cost;
    total.iterations += s.iterations;
    total.successful_iterations += s.successful_iterations;
    total.solve_ms += s.solve_ms;
    total.evaluation_ms += s.evaluation_ms;
    total.linear_solver_ms += s.linear_solver_ms;
    total.final_cost = s.final_cost;
    total.usable = s.usable;
    total.message = s.message;
    total.linear_solver = s.linear_solver;
  }
  // Back on level 0: points that lost every residual on the way are dropped.
  dropInvalidResiduals();
  total.num_points = numPoints();
  total.num_keyframes = numKeyframes();
  total.num_residuals = numResiduals();
  return total;
}

WindowSolveSummary SlidingWindow::solve() {
  WindowSolveSummary out;
  out.num_points = numPoints();
  out.num_keyframes = numKeyframes();
  out.num_residuals = numResiduals();
  if (out.num_residuals == 0) return out;

  // Elimination order, independent of memory addresses (Ceres orders the blocks within a
  // group by address): points first (group 0, eliminated; their slots make address order
  // deterministic, parameter_slots.hpp), then each keyframe's pose and affine blocks in a
  // group of their own, oldest first, then the intrinsics.
  ceres::Solver::Options solver;
  auto* ordering = new ceres::ParameterBlockOrdering;
  for (const auto& [pid, point] : points_) ordering->AddElementToGroup(&point->inverse_distance, 0);
  int group = 1, reduced_size = 0;
  auto addReduced = [&](double* block) {
    ordering->AddElementToGroup(block, group++);
    if (!problem_->IsParameterBlockConstant(block))
      reduced_size += problem_->ParameterBlockTangentSize(block);
  };
  for (const auto& kf : keyframes_) {
    addReduced(kf->pose.data());
    addReduced(kf->affine.data());
  }
  addReduced(intrinsics_.data());
  solver.linear_solver_ordering.reset(ordering);
  solver.linear_solver_type = reduced_size <= options_.dense_schur_max_size
                                  ? ceres::DENSE_SCHUR
                                  : ceres::SPARSE_SCHUR;
  solver.max_num_iterations = options_.max_iterations;
  solver.function_tolerance = options_.function_tolerance;
  solver.jacobi_scaling = options_.jacobi_scaling;
  solver.max_solver_time_in_seconds = options_.max_solver_time_s;
  solver.num_threads = options_.num_threads;
  solver.logging_type = ceres::SILENT;
  Stopwatch watch;
  ceres::Solver::Summary summary;
  evaluation_reuse_.arm(solver.max_num_iterations);
  ceres::Solve(solver, problem_.get(), &summary);
  evaluation_reuse_.disarm();
  all_residuals_valid_ = false;
  out.solve_ms = watch.elapsedMs();
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.successful_iterations = summary.num_successful_steps;
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  out.usable = summary.IsSolutionUsable();
  out.message = summary.message;
  out.evaluation_ms = 1e3 * (summary.residual_evaluation_time_in_seconds +
                             summary.jacobian_evaluation_time_in_seconds);
  out.linear_solver_ms = 1e3 * summary.linear_solver_time_in_seconds;
  out.linear_solver = ceres::LinearSolverTypeToString(summary.linear_solver_type_used);
  return out;
}

int SlidingWindow::removeOutliers() {
  return removeResiduals(options_.outlier_energy_per_pixel * kWindowPatternSize,
                         options_.min_residuals_per_point);
}

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

void SlidingWindow::removePoint(int id, bool marginalize) {
  WindowPoint& point = pointRef(id);
  double* block = &point.inverse_distance;
  if (marginalize && !point.residuals.empty()) {
    recordMarginalized(point);
    if (marginalizer_.marginalize(*problem_, {block})) has_prior_ = true;
    if (id == scale_anchor_point_id_) scale_fixed_by_prior_ = true;
  } else {
    problem_->RemoveParameterBlock(block);
    marginalizer_.forget(block);
  }
  if (id == scale_anchor_point_id_) scale_anchor_point_id_ = -1;
  erasePoint(id);
}

void SlidingWindow::erasePoint(int id) {
  const auto it = points_.find(id);
  inverse_distance_slots_.release(&it->second->inverse_distance);
  points_.erase(it);
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

void SlidingWindow::marginalizeKeyframe(int id) {
  WindowKeyframe& kf = keyframeRef(id);
  std::vector<int> newest_two;
  for (size_t i = keyframes_.size(); i-- > 0 && newest_two.size() < 2;)
    if (keyframes_[i]->id != id) newest_two.push_back(keyframes_[i]->id);

  // 1. Points hosted by the keyframe, or no longer observed by the two newest keyframes.
  std::vector<double*> to_marginalize;
  std::vector<int> marginalized_ids, dropped_ids;
  for (const auto& [pid, point] : points_) {
    bool observed_by_newest = false;
    for (int n : newest_two)
      observed_by_newest |= point->host_id == n || point->residuals.count(n) > 0;
    if (point->host_id != id && observed_by_newest) continue;
    if (point->residuals.empty()) {
      dropped_ids.push_back(pid);
    } else {
      to_marginalize.push_back(&point->inverse_distance);
      marginalized_ids.push_back(pid);
      recordMarginalized(*point);
    }
  }
  if (!to_marginalize.empty() && marginalizer_.marginalize(*problem_, to_marginalize))
    has_prior_ = true;
  for (int pid : marginalized_ids) {
    if (pid == scale_anchor_point_id_) {
      scale_fixed_by_prior_ = true;
      scale_anchor_point_id_ = -1;
    }
    erasePoint(pid);
  }
  for (int pid : dropped_ids) removePoint(pid, false);

  // 2. Residuals of the remaining points into this keyframe are dropped (sparsity).
  std::vector<int> emptied;
  for (auto& [pid, point] : points_) {
    const auto it = point->residuals.find(id);
    if (it == point->residuals.end()) continue;
    problem_->RemoveResidualBlock(it->second);
    point->residuals.erase(it);
    if (point->residuals.empty()) emptied.push_back(pid);
  }
  for (int pid : emptied) removePoint(pid, false);

  // 3. The keyframe's own blocks.
  if (marginalizer_.marginalize(*problem_, {kf.pose.data(), kf.affine.data()})) has_prior_ = true;
  if (id == anchor_keyframe_id_) anchor_keyframe_id_ = -1;
  keyframes_.erase(std::find_if(keyframes_.begin(), keyframes_.end(),
                                [id](const auto& k) { return k->id == id; }));
}

Eigen::Vector3d SlidingWindow::pointInWorld(const WindowPoint& point) const {
  const WindowKeyframe& host = keyframe(point.host_id);
  Eigen::Vector3d bearing;
  if (!factory_->unproject(intrinsics_, point.pixel, bearing))
    throw Error("SlidingWindow: point " + std::to_string(point.id) + " no longer unprojects");
  return host.T_world_cam() * (bearing / point.inverse_distance);
}

}  // namespace omnidso
