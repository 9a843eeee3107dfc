#include "omnidso/cameras/calibration/board_adjustment.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <limits>

#include "omnidso/cameras/model_fitting.hpp"
#include "omnidso/core/error.hpp"
#include "../penalised_projection.hpp"

namespace omnidso {
namespace {

// Residual of one detected corner: π(θ; exp(φ) X + t) − u (header formula).
template <typename Model>
struct BoardCornerResidual {
  Eigen::Vector3d board_point;
  Eigen::Vector2d detected;
  double penalty_px;

  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, T* residual) const {
    using ModelT = decltype(std::declval<Model>().template cast<T>());
    const ModelT model{typename ModelT::VecN(Eigen::Map<const typename ModelT::VecN>(intrinsics))};
    const Eigen::Matrix<T, 3, 1> phi(pose[0], pose[1], pose[2]);
    const Eigen::Matrix<T, 3, 1> t(pose[3], pose[4], pose[5]);
    const Eigen::Matrix<T, 3, 1> p = so3Exp(phi) * board_point.cast<T>() + t;
    detail::penalisedProjectionResidual(model, p, detected, penalty_px, residual);
    return true;
  }
};

using PoseBlock = Eigen::Matrix<double, 6, 1>;  // [φ, t]

PoseBlock toBlock(const SE3d& T) {
  PoseBlock b;
  b << so3Log(T.rotation()), T.translation();
  return b;
}
SE3d fromBlock(const PoseBlock& b) {
  return SE3d(so3Exp(Eigen::Vector3d(b.head<3>())), Eigen::Vector3d(b.tail<3>()));
}

template <typename Model>
BoardAdjustment adjustModel(const BoardDetections& detections, const BoardSpec& board,
                            const CornerSelection& selection, const Camera& start,
                            const std::vector<SE3d>& start_poses,
                            const AdjustmentOptions& options) {
  // Every parameter block in one buffer, the intrinsics first, then the poses in view order:
  // Ceres orders blocks by address (the Schur elimination within a group, and the columns of
  // ceres::Covariance's Jacobian), so a fixed layout keeps the results — the standard
  // deviations too — bit for bit independent of the heap.
  constexpr int kIntrinsics = Model::kNumParams;
  std::vector<double> blocks(kIntrinsics + 6 * start_poses.size());
  double* const intrinsics = blocks.data();
  const auto pose = [&](size_t v) { return blocks.data() + kIntrinsics + 6 * v; };
  Eigen::Map<Eigen::Matrix<double, kIntrinsics, 1>>{intrinsics} = start.params();
  for (size_t v = 0; v < start_poses.size(); ++v)
    Eigen::Map<PoseBlock>{pose(v)} = toBlock(start_poses[v]);
  const double penalty_px = std::hypot(detections.width, detections.height);

  ceres::Problem problem;
  for (size_t v = 0; v < detections.views.size(); ++v) {
    if (!selection.view_used[v]) continue;
    for (int k = 0; k < board.numCorners(); ++k) {
      if (!selection.corner_used[v][k]) continue;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<BoardCornerResidual<Model>, 2, Model::kNumParams, 6>(
              new BoardCornerResidual<Model>{board.corner(k), detections.views[v].corners[k],
                                             penalty_px}),
          new ceres::HuberLoss(options.huber_px), intrinsics, pose(v));
    }
  }
  setParameterBounds(problem, intrinsics, cameraParameterBounds(Model::kName));
  if (options.fix_poses)
    for (size_t v = 0; v < start_poses.size(); ++v)
      if (selection.view_used[v]) problem.SetParameterBlockConstant(pose(v));

  ceres::Solver::Options solver;
  solver.linear_solver_type = options.fix_poses ? ceres::DENSE_QR : ceres::DENSE_SCHUR;
  // Poses eliminated first (in view order: their addresses), then the intrinsics.
  if (!options.fix_poses) {
    solver.linear_solver_ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (size_t v = 0; v < start_poses.size(); ++v)
      if (selection.view_used[v])
        solver.linear_solver_ordering->AddElementToGroup(pose(v), 0);
    solver.linear_solver_ordering->AddElementToGroup(intrinsics, 1);
  }
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-15;
  solver.gradient_tolerance = 1e-15;
  solver.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  BoardAdjustment out{Camera::create(Model::kName,
                                     Eigen::Map<const Eigen::VectorXd>(intrinsics, kIntrinsics),
                                     detections.width,
                                     detections.height)};
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  out.usable = summary.IsSolutionUsable() && summary.termination_type != ceres::FAILURE;
  out.solver_message = summary.message;
  for (size_t v = 0; v < start_poses.size(); ++v)
    out.T_camera_board.push_back(
        selection.view_used[v] ? fromBlock(Eigen::Map<const PoseBlock>(pose(v))) : start_poses[v]);
  out.residuals = boardResiduals(detections, board, out.camera, out.T_camera_board);
  int used = 0;
  for (size_t v = 0; v < start_poses.size(); ++v) {
    if (!selection.view_used[v]) continue;
    for (int k = 0; k < board.numCorners(); ++k) {
      if (!selection.corner_used[v][k]) continue;
      const Eigen::Vector2d& r = out.residuals[v][k];
      out.sum_squared_px += r.allFinite() ? r.squaredNorm() : 2 * penalty_px * penalty_px;
      ++used;
    }
  }
  const int dof = 2 * used - Model::kNumParams - 6 * selection.numViews();
  out.noise_sigma_px = dof > 0 ? std::sqrt(out.sum_squared_px / dof) : 0.0;

  if (options.compute_covariance && dof > 0) {
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::DENSE_SVD;
    ceres::Covariance covariance(covariance_options);
    const std::vector<std::pair<const double*, const double*>> blocks = {
        {intrinsics, intrinsics}};
    if (covariance.Compute(blocks, &problem)) {
      Eigen::Matrix<double, Model::kNumParams, Model::kNumParams, Eigen::RowMajor> C;
      covariance.GetCovarianceBlock(intrinsics, intrinsics, C.data());
      out.param_stddev = C.diagonal().cwiseSqrt() * out.noise_sigma_px;
    }
  }
  return out;
}

template <size_t I = 0>
BoardAdjustment adjustByName(const BoardDetections& detections, const BoardSpec& board,
                             const CornerSelection& selection, const Camera& start,
                             const std::vector<SE3d>& start_poses,
                             const AdjustmentOptions& options) {
  if constexpr (I == std::variant_size_v<CameraModelVariant>) {
    throw Error("unknown camera model '" + start.modelName() + "'");
  } else {
    using Model = std::variant_alternative_t<I, CameraModelVariant>;
    if (start.model().index() == I)
      return adjustModel<Model>(detections, board, selection, start, start_poses, options);
    return adjustByName<I + 1>(detections, board, selection, start, start_poses, options);
  }
}

}  // namespace

CornerSelection CornerSelection::all(const BoardDetections& detections) {
  CornerSelection s;
  s.view_used.assign(detections.views.size(), true);
  for (const BoardView& view : detections.views) s.corner_used.emplace_back(view.corners.size(), true);
  return s;
}

int CornerSelection::numViews() const {
  return static_cast<int>(std::count(view_used.begin(), view_used.end(), true));
}

int CornerSelection::numCorners() const {
  int n = 0;
  for (size_t v = 0; v < view_used.size(); ++v)
    if (view_used[v]) n += static_cast<int>(std::count(corner_used[v].begin(), corner_used[v].end(), true));
  return n;
}

std::vector<std::vector<Eigen::Vector2d>> boardResiduals(const BoardDetections& detections,
                                                         const BoardSpec& board,
                                                         const Camera& camera,
                                                         const std::vector<SE3d>& poses) {
  const Eigen::Vector2d nan = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  std::vector<std::vector<Eigen::Vector2d>> residuals(detections.views.size());
  for (size_t v = 0; v < detections.views.size(); ++v) {
    for (int k = 0; k < board.numCorners(); ++k) {
      Eigen::Vector2d uv;
      const bool ok = std::visit(
          [&](const auto& m) { return m.project(poses[v] * board.corner(k), uv); }, camera.model());
      residuals[v].push_back(ok && uv.allFinite() ? Eigen::Vector2d(uv - detections.views[v].corners[k])
                                                  : nan);
    }
  }
  return residuals;
}

BoardAdjustment adjustBoards(const BoardDetections& detections, const BoardSpec& board,
                             const CornerSelection& selection, const Camera& start,
                             const std::vector<SE3d>& start_poses,
                             const AdjustmentOptions& options) {
  return adjustByName(detections, board, selection, start, start_poses, options);
}

}  // namespace omnidso
