// SlidingWindow (sliding_window.hpp): construction — the one persistent ceres::Problem with
// the intrinsics block — and read access to keyframes and points. The other jobs live in
// their own files: problem assembly (sliding_window_assembly.cc), solving
// (sliding_window_solve.cc), outlier removal (sliding_window_outliers.cc), the
// marginalisation step (sliding_window_marginalization.cc) and the refinement of a new
// point before activation (new_point_refinement.cc).
#include <ceres/loss_function.h>

#include <omnidso/backend/intrinsics_prior.hpp>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/backend/window_solver.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/residuals/se3_manifold.hpp>

namespace omnidso {

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
  checkOutlierThresholdOptions(options_.outlier_threshold);
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

Eigen::Vector3d SlidingWindow::pointInWorld(const WindowPoint& point) const {
  const WindowKeyframe& host = keyframe(point.host_id);
  Eigen::Vector3d bearing;
  if (!factory_->unproject(intrinsics_, point.pixel, bearing))
    throw Error("SlidingWindow: point " + std::to_string(point.id) + " no longer unprojects");
  return host.T_world_cam() * (bearing / point.inverse_distance);
}

}  // namespace omnidso
