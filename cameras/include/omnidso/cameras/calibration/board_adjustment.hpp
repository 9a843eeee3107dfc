#pragma once
// One Ceres problem over the intrinsics of one camera model and the poses of all board views
// (bundle adjustment of a calibration), autodiff through the model template.
//
//   minimise  Σ_views Σ_corners ρ(‖π(θ; R_v X_k + t_v) − u_vk‖²)
//
// π the model (its project()), θ its parameters, (R_v, t_v) = T_camera_board of view v with
// R_v = exp([φ_v]×) (core/se3.hpp so3Exp), X_k the board corner, u_vk the detected corner,
// ρ Huber with scale `huber_px`. A corner the model cannot project (outside its domain) adds
// a constant residual with zero derivative, so that steps into that region are rejected.
// Poses are eliminated by the Schur complement (DENSE_SCHUR; each pose touches only itself
// and θ), so a solve costs little more than its residual evaluations.
//
// Standard deviations of θ: ceres::Covariance (dense SVD) of the solution, i.e. (JᵀJ)⁻¹,
// scaled by σ̂² = Σ r² / (m − p) (m residuals, p = θ and 6 per view), the unbiased
// estimate of the corner noise variance, Hartley & Zisserman 2nd ed. Sec. 5.2.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "omnidso/cameras/calibration/board_detection.hpp"
#include "omnidso/cameras/camera.hpp"
#include "omnidso/core/se3.hpp"

namespace omnidso {

// Which views and corners take part (outliers are dropped by clearing them).
struct CornerSelection {
  std::vector<bool> view_used;                 // per view
  std::vector<std::vector<bool>> corner_used;  // per view, per corner

  static CornerSelection all(const BoardDetections& detections);
  int numViews() const;
  int numCorners() const;  // of the used views
};

struct AdjustmentOptions {
  double huber_px = 1.0;
  int max_iterations = 200;
  bool compute_covariance = true;
  bool fix_poses = false;  // intrinsics only (screening starts against known poses)
};

struct BoardAdjustment {
  Camera camera;
  std::vector<SE3d> T_camera_board{};  // per view (unused views keep their start)
  // Per view, per corner: projection − detection (px); NaN where the model cannot project.
  std::vector<std::vector<Eigen::Vector2d>> residuals{};
  Eigen::VectorXd param_stddev{};  // empty when the covariance is rank deficient
  double noise_sigma_px = 0.0;   // σ̂ per residual component
  double sum_squared_px = 0.0;   // Σ ‖r‖² over the used corners
  int iterations = 0;
  bool converged = false;
  // False when Ceres refused the problem or failed (the parameters are then the start's,
  // which must never be reported as a calibration); solver_message says why.
  bool usable = false;
  std::string solver_message{};
};

// Throws omnidso::Error for an unknown model name.
BoardAdjustment adjustBoards(const BoardDetections& detections, const BoardSpec& board,
                             const CornerSelection& selection, const Camera& start,
                             const std::vector<SE3d>& start_poses,
                             const AdjustmentOptions& options = AdjustmentOptions());

// projection − detection for every corner of every view (NaN outside the model's domain).
std::vector<std::vector<Eigen::Vector2d>> boardResiduals(const BoardDetections& detections,
                                                         const BoardSpec& board,
                                                         const Camera& camera,
                                                         const std::vector<SE3d>& poses);

}  // namespace omnidso
