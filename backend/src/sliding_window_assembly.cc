// SlidingWindow's problem assembly (sliding_window.hpp): keyframes enter with their pose and
// affine parameter blocks (the first one held constant: the pose and brightness gauge), points
// with their inverse-distance block, and one photometric residual block per (point, target
// keyframe) pair whose projection is valid — eq. 5–7 with DSO's 8-pixel pattern, wrapped in
// OutOfBoundsPenalty and, when evaluations are reused, in ReusingCostFunction. Where the native
// solver solves level 0, a residual's block is deferred: the point records its target, and
// the block enters the ceres::Problem only when a Ceres path needs it (sliding_window.hpp).
#include <omnidso/backend/affine_prior.hpp>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <omnidso/residuals/reusing_cost_function.hpp>

namespace omnidso {

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
    if (!hostPatchFits<kWindowPatternSize>(image, pixel, options_.pattern_spread))
      return std::nullopt;
    obs.host = makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(level), pixel,
                                                 options_.gradient_weight_c,
                                                 host.pyramid->encodingSlope(level),
                                                 options_.pattern_spread);
  }
  obs.target_image = &target.pyramid->level(level);
  obs.target_content = target.pyramid->content(level);
  obs.gradient = imageGradient(options_.central_difference_gradients);
  obs.host_exposure = host.exposure;
  obs.target_exposure = target.exposure;
  obs.level = level;
  return obs;
}

bool SlidingWindow::addResidual(WindowPoint& point, WindowKeyframe& target, int level) {
  const std::optional<WindowObservation> obs = observation(point, target, level);
  if (!obs) return false;
  std::array<double*, 6> blocks = residualParameters(point, target);
  if (factory_->status(*obs, blocks.data()) != PhotometricStatus::kValid) return false;
  point.residuals[target.id] = defersResidualBlocks(level) ? nullptr : addResidualBlock(blocks, *obs);
  return true;
}

std::array<double*, 6> SlidingWindow::residualParameters(WindowPoint& point,
                                                         WindowKeyframe& target) {
  WindowKeyframe& host = keyframeRef(point.host_id);
  return {host.pose.data(),   target.pose.data(),   &point.inverse_distance,
          host.affine.data(), target.affine.data(), intrinsics_.data()};
}

OutOfBoundsPenalty* SlidingWindow::makeResidualCost(const WindowObservation& obs) {
  ceres::CostFunction* cost = factory_->makeCost(options_.differentiation, obs);
  if (options_.reuse_evaluations) cost = new ReusingCostFunction(cost, &evaluation_reuse_);
  return new OutOfBoundsPenalty(cost, options_.outlier_energy_per_pixel * kWindowPatternSize);
}

ceres::ResidualBlockId SlidingWindow::addResidualBlock(std::array<double*, 6>& blocks,
                                                       const WindowObservation& obs) {
  return problem_->AddResidualBlock(makeResidualCost(obs), loss_.get(), blocks.data(),
                                    static_cast<int>(blocks.size()));
}

bool SlidingWindow::defersResidualBlocks(int level) const {
  return level == 0 && nativeSolverApplies();
}

void SlidingWindow::materializeResidualBlocks(WindowPoint& point) {
  for (auto& [target_id, id] : point.residuals) {
    if (id) continue;
    WindowKeyframe& target = keyframeRef(target_id);
    std::array<double*, 6> blocks = residualParameters(point, target);
    // Level 0 (only level-0 blocks are deferred), whose observation always exists.
    id = addResidualBlock(blocks, *observation(point, target, 0));
  }
}

void SlidingWindow::materializeResidualBlocks() {
  for (auto& [pid, point] : points_) materializeResidualBlocks(*point);
}

void SlidingWindow::removeResidualBlock(ceres::ResidualBlockId id) {
  if (id) problem_->RemoveResidualBlock(id);
}

double SlidingWindow::residualEnergy(WindowPoint& point, int target_id,
                                     ceres::ResidualBlockId id) {
  if (id) return rawEnergy(*problem_, id);
  WindowKeyframe& target = keyframeRef(target_id);
  const std::unique_ptr<OutOfBoundsPenalty> cost(makeResidualCost(*observation(point, target, 0)));
  const std::array<double*, 6> blocks = residualParameters(point, target);
  return cost->rawEnergy(blocks.data());
}

int SlidingWindow::addPoint(int host_id, const Eigen::Vector2d& pixel, double inverse_distance) {
  const WindowKeyframe& host = keyframe(host_id);
  const ImageF& image = host.pyramid->level(0);
  if (!hostPatchFits<kWindowPatternSize>(image, pixel, options_.pattern_spread)) return -1;
  auto point = std::make_unique<WindowPoint>(*inverse_distance_slots_.acquire());
  point->id = next_point_id_;
  point->host_id = host_id;
  point->pixel = pixel;
  point->inverse_distance = inverse_distance;
  point->patch = makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(0), pixel,
                                                   options_.gradient_weight_c,
                                                   host.pyramid->encodingSlope(0),
                                                   options_.pattern_spread);
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

}  // namespace omnidso
