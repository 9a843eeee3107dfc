#pragma once
// Private to coarse_tracker.cc: one pyramid level's tracking residuals r_i(T, a, b) as the
// native tracker solver sees them (tracker_solver.hpp, TrackerResiduals) — the kernel of the
// Ceres cost function (evaluateTrackingResidual) with R and t formed once per point and one
// sampler of the frame's level image for all observations — and the level's error
// (TrackingLevelSolve::rmse), the same for both solvers.

#include <algorithm>
#include <cmath>
#include <omnidso/core/se3.hpp>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/tracker_solver.hpp>
#include <omnidso/residuals/tracking_residual.hpp>
#include <vector>

namespace omnidso {

// One level's tracking residuals for the native solver (tracker_solver.hpp): the
// observations with the frame's exposure, one sampler of the frame's level image for all,
// R and t formed once per point (evaluateTrackingResidual).
template <template <typename> class M>
class LevelResiduals final : public TrackerResiduals {
 public:
  LevelResiduals(const M<double>& level_camera,
                 const std::vector<TrackingObservation<1>>& observations, const ImageF& image,
                 const Mask* content, double frame_exposure)
      : camera_(level_camera),
        observations_(observations),
        sampler_(image,
                 observations.empty() ? ImageInterpolation::kBilinear
                                      : observations.front().interpolation,
                 content,
                 observations.empty() ? ImageGradient::kInterpolant
                                      : observations.front().gradient) {
    for (TrackingObservation<1>& obs : observations_) obs.target_exposure = frame_exposure;
  }

  int size() const override { return static_cast<int>(observations_.size()); }
  void setPoint(const double* pose, const double* affine) override {
    const SE3d T = SE3d::fromParameters(pose);
    R_ = T.rotationMatrix();
    t_ = T.translation();
    affine_[0] = affine[0];
    affine_[1] = affine[1];
  }
  bool evaluate(int i, double* residual, double* jacobian) const override {
    TrackingPoseJacobian<1> J_pose;
    TrackingAffineJacobian<1> J_affine;
    const bool valid =
        evaluateTrackingResidual<M, 1>(camera_, observations_[static_cast<size_t>(i)], sampler_,
                                       R_, t_, affine_, residual, jacobian ? &J_pose : nullptr,
                                       jacobian ? &J_affine : nullptr) == PhotometricStatus::kValid;
    if (valid && jacobian) {
      std::copy_n(J_pose.data(), 6, jacobian);
      std::copy_n(J_affine.data(), 2, jacobian + 6);
    }
    return valid;
  }

 private:
  M<double> camera_;
  std::vector<TrackingObservation<1>> observations_;
  ImageSampler sampler_;
  Eigen::Matrix3d R_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_ = Eigen::Vector3d::Zero();
  double affine_[2] = {0.0, 0.0};
};

// The level's error: RMS of the Huber-clamped residuals that are valid (DSO does the same, so
// that a few outliers do not dominate); `evaluate(i, &r)` false where residual i is invalid.
template <typename Evaluate>
TrackingLevelSolve levelError(int n, double huber_threshold, Evaluate&& evaluate) {
  TrackingLevelSolve out;
  double sum = 0.0;
  int valid = 0;
  for (int i = 0; i < n; ++i) {
    double r;
    if (!evaluate(i, &r)) continue;
    const double a = std::abs(r);
    sum += a <= huber_threshold ? r * r : huber_threshold * (2 * a - huber_threshold);
    ++valid;
  }
  if (valid > 0) out.rmse = std::sqrt(sum / valid);
  out.valid_fraction = n == 0 ? 0.0 : static_cast<double>(valid) / n;
  return out;
}

}  // namespace omnidso
