// SlidingWindow's native solve (window_solver.hpp): the window's ceres::Problem as the native
// solver sees it — the same parameter blocks and constant blocks (the gauge), the photometric
// residuals in point-id and keyframe order, every other residual block as a prior — and the
// solve, reported in the same WindowSolveSummary as the Ceres path.
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/backend/window_solver.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

namespace omnidso {

ceres::Problem& SlidingWindow::mutableProblem() {
  all_residuals_valid_ = false;
  materializeResidualBlocks();
  return *problem_;
}

WindowProblem SlidingWindow::nativePhotometricProblem(const std::vector<const WindowPoint*>& points) {
  WindowProblem native;
  std::map<int, int> frame_index;  // keyframe id → index, oldest first
  for (const auto& kf : keyframes_) {
    WindowFrame f;
    f.pose = kf->pose.data();
    f.affine = kf->affine.data();
    f.pose_constant = problem_->IsParameterBlockConstant(f.pose);
    f.affine_constant = problem_->IsParameterBlockConstant(f.affine);
    f.exposure = kf->exposure;
    f.image = &kf->pyramid->level(0);
    f.content = kf->pyramid->content(0);
    frame_index[kf->id] = static_cast<int>(native.frames.size());
    native.frames.push_back(f);
  }
  for (const WindowPoint* point : points) {
    WindowPointBlock b;
    b.inverse_distance = &point->inverse_distance;
    b.constant = problem_->IsParameterBlockConstant(b.inverse_distance);
    b.host = frame_index.at(point->host_id);
    b.patch = &point->patch;
    b.first_residual = static_cast<int>(native.residuals.size());
    b.num_residuals = static_cast<int>(point->residuals.size());
    for (const auto& [target, id] : point->residuals)
      native.residuals.push_back({static_cast<int>(native.points.size()), frame_index.at(target)});
    native.points.push_back(b);
  }
  native.intrinsics = intrinsics_.data();
  native.num_intrinsics = static_cast<int>(intrinsics_.size());
  native.intrinsics_constant = problem_->IsParameterBlockConstant(intrinsics_.data());
  native.pose_manifold = pose_manifold_.get();
  native.photometric_loss = loss_.get();
  native.interpolation = WindowObservation{}.interpolation;
  native.gradient = imageGradient(options_.central_difference_gradients);
  native.out_of_bounds_energy = options_.outlier_energy_per_pixel * kWindowPatternSize;
  if (!window_terms_) window_terms_ = factory_->makeWindowTerms();
  native.photometric = window_terms_;
  native.id = ++num_native_problems_;
  native.pool = pool_;
  return native;
}

std::optional<WindowProblem> SlidingWindow::nativeProblem() {
  std::vector<const WindowPoint*> points;
  for (const auto& [pid, point] : points_) points.push_back(point.get());
  WindowProblem native = nativePhotometricProblem(points);
  // Priors: every residual block that is not a photometric one (those are all
  // OutOfBoundsPenalty, addResidual), over keyframe blocks and the intrinsics.
  std::vector<ceres::ResidualBlockId> blocks;
  problem_->GetResidualBlocks(&blocks);
  std::vector<double*> parameters;
  for (ceres::ResidualBlockId id : blocks) {
    const ceres::CostFunction* cost = problem_->GetCostFunctionForResidualBlock(id);
    if (dynamic_cast<const OutOfBoundsPenalty*>(cost)) continue;
    WindowPrior prior;
    prior.cost = cost;
    prior.loss = problem_->GetLossFunctionForResidualBlock(id);
    problem_->GetParameterBlocksForResidualBlock(id, &parameters);
    for (double* values : parameters) {
      WindowPriorBlock b;
      b.values = values;
      b.ambient_size = problem_->ParameterBlockSize(values);
      b.tangent_size = problem_->ParameterBlockTangentSize(values);
      b.manifold = problem_->GetManifold(values);
      b.constant = problem_->IsParameterBlockConstant(values);
      b.tangent_offset = -1;
      for (size_t f = 0; f < native.frames.size(); ++f) {
        const int offset = kFrameTangentSize * static_cast<int>(f);
        if (values == native.frames[f].pose) b.tangent_offset = offset;
        if (values == native.frames[f].affine) b.tangent_offset = offset + 6;
      }
      if (values == native.intrinsics) b.tangent_offset = native.intrinsicsOffset();
      if (b.tangent_offset < 0) return std::nullopt;  // e.g. a prior on a point
      prior.blocks.push_back(b);
    }
    native.priors.push_back(std::move(prior));
  }
  return native;
}

std::optional<WindowProblem> SlidingWindow::firstEstimateProblem(const WindowProblem& problem) {
  WindowProblem first_estimate = problem;
  first_estimate_values_.clear();
  first_estimate_values_.reserve(2 * problem.frames.size() + 1);  // the pointers stay valid
  // Constant blocks are known: at x, as Marginalizer evaluates them.
  auto atFirstEstimate = [&](double* block, bool constant) {
    const Eigen::VectorXd* x_bar = constant ? nullptr : marginalizer_.linearizationPoint(block);
    if (!x_bar) return block;
    first_estimate_values_.push_back(*x_bar);
    return first_estimate_values_.back().data();
  };
  for (WindowFrame& frame : first_estimate.frames) {
    frame.pose = atFirstEstimate(frame.pose, frame.pose_constant);
    frame.affine = atFirstEstimate(frame.affine, frame.affine_constant);
  }
  first_estimate.intrinsics =
      atFirstEstimate(first_estimate.intrinsics, first_estimate.intrinsics_constant);
  if (first_estimate_values_.empty()) return std::nullopt;  // no prior yet: x̄ = x
  return first_estimate;
}

WindowSolveSummary SlidingWindow::solveNative(const WindowProblem& problem,
                                              WindowSolveSummary out) {
  WindowSolverOptions options;
  options.max_num_iterations = options_.max_iterations;
  options.function_tolerance = options_.function_tolerance;
  options.max_solver_time_in_seconds = options_.max_solver_time_s;
  const Stopwatch watch;
  if (!solver_workspace_) solver_workspace_ = std::make_unique<WindowSolverWorkspace>();
  const std::optional<WindowProblem> first_estimate =
      options_.first_estimate_jacobians ? firstEstimateProblem(problem) : std::nullopt;
  WindowSolverSummary s = solveWindow(problem, options, solver_workspace_.get(),
                                      first_estimate ? &*first_estimate : nullptr);
  all_residuals_valid_ = false;
  solved_energies_ = std::move(s.residual_energies);
  solved_fingerprint_ = solved_energies_.empty() ? std::vector<double>{} : energyFingerprint();
  out.solve_ms = watch.elapsedMs();
  out.iterations = s.iterations;
  out.successful_iterations = s.successful_steps;
  out.initial_cost = s.initial_cost;
  out.final_cost = s.final_cost;
  out.usable = s.usable();
  out.message = s.message;
  out.evaluation_ms = s.evaluation_ms;
  out.linear_solver_ms = s.linear_solver_ms;
  out.linear_solver = "NATIVE_DENSE_SCHUR";
  return out;
}

std::vector<double> SlidingWindow::energyFingerprint() const {
  std::vector<double> f;
  f.reserve(10 * keyframes_.size() + 4 * points_.size() + intrinsics_.size());
  for (const auto& kf : keyframes_) {
    f.push_back(kf->id);
    f.insert(f.end(), kf->pose.begin(), kf->pose.end());
    f.insert(f.end(), kf->affine.begin(), kf->affine.end());
  }
  for (const auto& [pid, point] : points_) {
    f.push_back(pid);
    f.push_back(point->host_id);
    f.push_back(point->inverse_distance);
    f.push_back(static_cast<double>(point->residuals.size()));
    for (const auto& [target, id] : point->residuals) f.push_back(target);
  }
  f.insert(f.end(), intrinsics_.data(), intrinsics_.data() + intrinsics_.size());
  return f;
}

}  // namespace omnidso
