// SlidingWindow's solving (sliding_window.hpp): the scale gauge held by a constant inverse
// distance (chosen before the first solve, and again whenever that point has left),
// invalid residuals dropped before each one, and Ceres's Levenberg–Marquardt with the points
// eliminated first by the Schur complement, in an elimination order that does not depend on
// memory addresses (bit-for-bit results) — or, where WindowOptions::native_solver allows
// it, the native solver (sliding_window_native.cc); optimizeCoarseToFine solves the same
// problem on each pyramid level in turn.
#include <ceres/ordered_groups.h>
#include <ceres/solver.h>

#include <algorithm>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/core/timing.hpp>

namespace omnidso {

void SlidingWindow::holdScaleAnchor() {
  if (scale_anchor_point_id_ >= 0 || scale_fixed_by_prior_ || points_.empty()) return;
  // The point with the most residuals, preferring the pose anchor's own points; ties go to
  // the lowest id, so the choice is deterministic. A later anchor takes its value from the
  // window as it is: it keeps the scale the window has, and takes the similarity direction
  // out of the solves that follow.
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

WindowSolveSummary SlidingWindow::optimize() {
  // Residuals whose projection has left the image (or the model's domain) since they were
  // made would only carry the constant penalty: dropped, as DSO drops out-of-bounds residuals.
  // Skipped when nothing has moved since the last pass (the odometry's removeOutliers after
  // the previous solve; new residuals are only added where valid).
  if (!all_residuals_valid_) dropInvalidResiduals();
  holdScaleAnchor();
  return solve(0);
}

void SlidingWindow::rebuildResiduals(int level,
                                     const std::map<int, std::vector<int>>& targets_by_point) {
  for (auto& [pid, point] : points_) {
    for (const auto& [target, id] : point->residuals) removeResidualBlock(id);
    point->residuals.clear();
    for (int target : targets_by_point.at(pid)) addResidual(*point, keyframeRef(target), level);
  }
}

WindowSolveSummary SlidingWindow::optimizeCoarseToFine(int num_levels) {
  dropInvalidResiduals();
  holdScaleAnchor();
  std::map<int, std::vector<int>> targets;
  for (const auto& [pid, point] : points_)
    for (const auto& [target, id] : point->residuals) targets[pid].push_back(target);
  const int coarsest = std::min(num_levels, keyframes_.front()->pyramid->numLevels()) - 1;
  WindowSolveSummary total;
  total.initial_cost = std::numeric_limits<double>::quiet_NaN();
  for (int level = coarsest; level >= 0; --level) {
    rebuildResiduals(level, targets);
    const WindowSolveSummary s = solve(level);
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

bool SlidingWindow::nativeSolverApplies() const {
  return options_.native_solver && options_.differentiation == DifferentiationMode::kAnalytic &&
         !options_.jacobi_scaling;
}

WindowSolveSummary SlidingWindow::solve(int level) {
  WindowSolveSummary out;
  out.num_points = numPoints();
  out.num_keyframes = numKeyframes();
  out.num_residuals = numResiduals();
  if (out.num_residuals == 0) return out;
  if (level == 0 && nativeSolverApplies()) {
    if (const std::optional<WindowProblem> native = nativeProblem()) return solveNative(*native, out);
  }
  materializeResidualBlocks();  // Ceres solves every residual

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

}  // namespace omnidso
