#include <ceres/ceres.h>

#include <cmath>
#include <omnidso/backend/affine_prior.hpp>
#include <omnidso/frontend/affine_gauge.hpp>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/model_dispatch.hpp>
#include <omnidso/frontend/tracker_solver.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <omnidso/residuals/tracking_residual.hpp>

#include "tracker_level_residuals.hpp"
#include "tracker_reference.hpp"

namespace omnidso {
struct CoarseTracker::Impl {
  Camera camera;
  CoarseTrackerOptions options;
  std::unique_ptr<const TrackerReference> reference;
  using LevelObservations = TrackerReference::LevelObservations;
  // What one pass over the hypotheses aligns, and its iteration budget per level.
  struct Pass {
    const LevelObservations& observations;
    const std::vector<int>& max_iterations;
    int maxIterations(int level) const {
      return max_iterations[std::min<size_t>(level, max_iterations.size() - 1)];
    }
  };
  Pass plainPass() const { return {reference->observations(), options.max_iterations}; }
  SE3Manifold manifold;

  Impl(const Camera& c, CoarseTrackerOptions o) : camera(c), options(std::move(o)) {}

  // With `affine_in_reference_gauge`, the frame's [a, b] in the reference's gauge,
  // b' = b − s b_ref, and back (header, "The affine gauge"); s = t e^a / (t_ref e^a_ref) is the
  // same in both, a unchanged. Without it the tracker works in the window's gauge.
  Eigen::Vector2d toReferenceGauge(const Eigen::Vector2d& ab, double frame_exposure) const {
    if (!options.affine_in_reference_gauge) return ab;
    const double s = brightnessGain(frame_exposure, ab.x(), reference->exposure(),
                                    reference->affine().x());
    return {ab.x(), ab.y() - s * reference->affine().y()};
  }
  Eigen::Vector2d fromReferenceGauge(const Eigen::Vector2d& ab, double frame_exposure) const {
    if (!options.affine_in_reference_gauge) return ab;
    const double s = brightnessGain(frame_exposure, ab.x(), reference->exposure(),
                                    reference->affine().x());
    return {ab.x(), ab.y() + s * reference->affine().y()};
  }

  template <template <typename> class M>
  TrackingLevelSolve solveLevel(ModelTag<M>, const M<double>& model, int level,
                                const ImagePyramid& frame, double frame_exposure, double* pose,
                                double* frame_affine, bool optimise,
                                const Pass* pass = nullptr) const {
    const Pass plain = plainPass();
    if (!pass) pass = &plain;
    const std::vector<TrackingObservation<1>>& level_observations = pass->observations[level];
    const M<double> level_model = TrackerReference::levelModel(model, level);
    if (options.native_solver)
      return solveLevelNative(level_model, level, level_observations, pass->maxIterations(level),
                              frame, frame_exposure, pose, frame_affine, optimise);
    std::vector<std::unique_ptr<OutOfBoundsPenalty>> costs;
    costs.reserve(level_observations.size());
    for (TrackingObservation<1> obs : level_observations) {
      obs.target_image = &frame.level(level);
      obs.target_content = frame.content(level);
      obs.target_exposure = frame_exposure;
      costs.emplace_back(std::make_unique<OutOfBoundsPenalty>(
          makeTrackingCost<M, 1>(DifferentiationMode::kAnalytic, level_model, obs),
          kDsoOutlierEnergyPerPixel));
    }
    int iterations = -1;
    if (optimise && !costs.empty()) {
      ceres::Problem::Options po;
      po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
      ceres::Problem problem(po);
      ceres::HuberLoss loss(options.huber_threshold);
      problem.AddParameterBlock(pose, 7, const_cast<SE3Manifold*>(&manifold));
      problem.AddParameterBlock(frame_affine, 2);
      const double* params_ptr[] = {pose, frame_affine};
      double r[2];  // one residual; sized so that no cost function type can overrun it
      int added = 0;
      for (auto& cost : costs) {
        if (!cost->inner().Evaluate(params_ptr, r, nullptr)) continue;  // starts invalid: left out
        problem.AddResidualBlock(cost.get(), &loss, pose, frame_affine);
        ++added;
      }
      AffinePrior prior(Eigen::Vector2d(frame_affine[0], frame_affine[1]),
                        options.affine_prior_weight_a, options.affine_prior_weight_b);
      if (options.affine_prior_weight_a > 0 || options.affine_prior_weight_b > 0)
        problem.AddResidualBlock(&prior, nullptr, frame_affine);
      if (added >= 8) {
        ceres::Solver::Options so;
        so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
        so.max_num_iterations = pass->maxIterations(level);
        so.num_threads = options.num_threads;
        so.function_tolerance = options.function_tolerance;
        so.logging_type = ceres::SILENT;
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        iterations = static_cast<int>(summary.iterations.size()) - 1;
      }
    }
    // Error of the result.
    const double* params_ptr[] = {pose, frame_affine};
    TrackingLevelSolve out =
        levelError(static_cast<int>(costs.size()), options.huber_threshold, [&](int i, double* r) {
          double residual[2];  // see above
          const bool valid = costs[static_cast<size_t>(i)]->inner().Evaluate(params_ptr, residual,
                                                                             nullptr);
          *r = valid ? residual[0] : 0.0;
          return valid;
        });
    out.iterations = iterations;
    return out;
  }

  // solveLevel by the native solver (tracker_solver.hpp): the same problem — residuals
  // valid at the start, the out-of-bounds penalty, Huber, the affine prior about the level's
  // starting affine, at least 8 residuals — and the same error of the result.
  template <template <typename> class M>
  TrackingLevelSolve solveLevelNative(const M<double>& level_model, int level,
                                      const std::vector<TrackingObservation<1>>& level_observations,
                                      int max_iterations, const ImagePyramid& frame,
                                      double frame_exposure,
                                      double* pose, double* frame_affine, bool optimise) const {
    LevelResiduals<M> residuals(level_model, level_observations, frame.level(level),
                                frame.content(level), frame_exposure);
    int iterations = -1;
    if (optimise && residuals.size() > 0) {
      TrackerProblem problem;
      problem.residuals = &residuals;
      problem.huber_threshold = options.huber_threshold;
      problem.invalid_residual = std::sqrt(kDsoOutlierEnergyPerPixel);  // one pixel per point
      problem.affine_prior_mean = Eigen::Vector2d(frame_affine[0], frame_affine[1]);
      problem.affine_prior_weight_a = options.affine_prior_weight_a;
      problem.affine_prior_weight_b = options.affine_prior_weight_b;
      problem.min_residuals = 8;
      TrackerSolverOptions so;
      so.max_num_iterations = max_iterations;
      so.function_tolerance = options.function_tolerance;
      const TrackerSolverSummary summary = solveTracker(problem, so, pose, frame_affine);
      if (summary.termination != TrackerTermination::kNotSolved) iterations = summary.iterations;
    }
    residuals.setPoint(pose, frame_affine);
    TrackingLevelSolve out = levelError(residuals.size(), options.huber_threshold,
                                        [&](int i, double* r) {
                                          return residuals.evaluate(i, r, nullptr);
                                        });
    out.iterations = iterations;
    return out;
  }

  // RMS distance (level-0 px) between where the two poses put the level-0 points.
  template <template <typename> class M>
  double rmsShiftBetween(const M<double>& model, const SE3d& T_a, const SE3d& T_b) const {
    double sum = 0.0;
    int n = 0;
    const Eigen::Matrix3d R_a = T_a.rotationMatrix(), R_b = T_b.rotationMatrix();
    const std::vector<Eigen::Vector2d>& pixels = reference->finestPixels();
    for (size_t i = 0; i < pixels.size(); ++i) {
      Eigen::Vector3d b;
      if (!model.unproject(pixels[i], b)) continue;
      const double d = reference->finestInverseDistances()[i];
      Eigen::Vector2d u_a, u_b;
      if (!model.project(R_a * b + d * T_a.translation(), u_a) ||
          !model.project(R_b * b + d * T_b.translation(), u_b))
        continue;
      sum += (u_a - u_b).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(sum / n) : 0.0;
  }

  // The hypotheses, most likely first, each coarse to fine in `pass`, dropped after a level
  // whose error exceeds `early_reject_factor` × the best so far at that level; trying stops
  // once one ends below `good_enough_factor` × `previous_rmse`. The best by finest-level
  // error, and the hypothesis it started from.
  template <template <typename> class M>
  TrackingResult tryHypotheses(ModelTag<M> tag, const M<double>& model, const ImagePyramid& frame,
                               double frame_exposure, int levels,
                               const std::vector<SE3d>& hypotheses, const Eigen::Vector2d& start,
                               double previous_rmse, const Pass& pass,
                               SE3d* winning_hypothesis) const {
    TrackingResult best;
    std::vector<double> best_coarse_rmse(levels, std::numeric_limits<double>::infinity());
    double best_final = std::numeric_limits<double>::infinity();
    for (const SE3d& hypothesis : hypotheses) {
      ++best.hypotheses_tried;
      std::array<double, 7> pose;
      hypothesis.toParameters(pose.data());
      std::array<double, 2> frame_affine = {start.x(), start.y()};
      std::vector<double> level_rmse(levels, std::numeric_limits<double>::infinity());
      bool rejected = false;
      TrackingLevelSolve finest;
      for (int level = levels - 1; level >= 0; --level) {
        const TrackingLevelSolve r = solveLevel(tag, model, level, frame, frame_exposure,
                                                pose.data(), frame_affine.data(), true, &pass);
        level_rmse[level] = r.rmse;
        finest = r;
        if (!std::isfinite(r.rmse) ||
            r.rmse > options.early_reject_factor * best_coarse_rmse[level]) {
          rejected = true;
          break;
        }
        best_coarse_rmse[level] = std::min(best_coarse_rmse[level], r.rmse);
      }
      if (rejected || finest.valid_fraction < options.min_valid_fraction) continue;
      if (finest.rmse < best_final) {
        best_final = finest.rmse;
        best.ok = true;
        best.T_frame_ref = SE3d::fromParameters(pose.data());
        best.affine = fromReferenceGauge(Eigen::Vector2d(frame_affine[0], frame_affine[1]),
                                         frame_exposure);
        best.level_rmse = level_rmse;
        best.rmse = finest.rmse;
        best.valid_fraction = finest.valid_fraction;
        *winning_hypothesis = hypothesis;
      }
      if (goodEnough(best, previous_rmse)) break;
    }
    return best;
  }

  // DSO's re-track test: a result below `good_enough_factor` × the previous frame's error
  // ends the trying (and needs no retry).
  bool goodEnough(const TrackingResult& result, double previous_rmse) const {
    return result.ok && std::isfinite(previous_rmse) &&
           result.rmse < options.good_enough_factor * previous_rmse;
  }

  // RMS pixel shifts of the level-0 points under translation only and under the full motion.
  template <template <typename> class M>
  void flow(ModelTag<M>, const M<double>& model, const SE3d& T, TrackingResult* result) const {
    double sum_t = 0.0, sum_rt = 0.0;
    int n = 0;
    const Eigen::Matrix3d R = T.rotationMatrix();
    const std::vector<Eigen::Vector2d>& pixels = reference->finestPixels();
    for (size_t i = 0; i < pixels.size(); ++i) {
      Eigen::Vector3d b;
      if (!model.unproject(pixels[i], b)) continue;
      const double d = reference->finestInverseDistances()[i];
      Eigen::Vector2d u_t, u_rt;
      if (!model.project(b + d * T.translation(), u_t) ||
          !model.project(R * b + d * T.translation(), u_rt))
        continue;
      sum_t += (u_t - pixels[i]).squaredNorm();
      sum_rt += (u_rt - pixels[i]).squaredNorm();
      ++n;
    }
    result->flow_t = n ? std::sqrt(sum_t / n) : 0.0;
    result->flow_rt = n ? std::sqrt(sum_rt / n) : 0.0;
  }
};

CoarseTracker::CoarseTracker(const Camera& camera, CoarseTrackerOptions options)
    : impl_(std::make_unique<Impl>(camera, std::move(options))) {}

CoarseTracker::~CoarseTracker() = default;

bool CoarseTracker::hasReference() const { return impl_->reference != nullptr; }

int CoarseTracker::numReferencePoints(int level) const {
  if (!hasReference() || level < 0 ||
      level >= static_cast<int>(impl_->reference->observations().size()))
    return 0;
  return static_cast<int>(impl_->reference->observations()[level].size());
}

void CoarseTracker::setReference(std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                                 const Eigen::Vector2d& affine,
                                 const std::vector<TrackingReferencePoint>& points) {
  auto reference =
      std::make_unique<TrackerReference>(std::move(pyramid), exposure, affine, impl_->options);
  withResidualModel<void>(impl_->camera,
                          [&](auto, const auto& model) { reference->build(model, points); });
  impl_->reference = std::move(reference);
}

TrackingLevelSolve CoarseTracker::solveLevel(const ImagePyramid& frame, double exposure, int level,
                                             SE3d* T_frame_ref, Eigen::Vector2d* affine) const {
  if (!hasReference() || level < 0 ||
      level >= static_cast<int>(impl_->reference->observations().size()) ||
      level >= frame.numLevels())
    return {};
  std::array<double, 7> pose;
  T_frame_ref->toParameters(pose.data());
  const Eigen::Vector2d start = impl_->toReferenceGauge(*affine, exposure);
  std::array<double, 2> ab = {start.x(), start.y()};
  const TrackingLevelSolve out =
      withResidualModel<TrackingLevelSolve>(impl_->camera, [&](auto tag, const auto& model) {
        return impl_->solveLevel(tag, model, level, frame, exposure, pose.data(), ab.data(), true);
      });
  *T_frame_ref = SE3d::fromParameters(pose.data());
  *affine = impl_->fromReferenceGauge(Eigen::Vector2d(ab[0], ab[1]), exposure);
  return out;
}

std::vector<SE3d> CoarseTracker::makeHypotheses(const SE3d& T_last_ref,
                                                const SE3d& velocity) const {
  const SE3d half = SE3d::exp(0.5 * velocity.log());
  const SE3d predicted = velocity * T_last_ref;
  std::vector<SE3d> out = {predicted, velocity * velocity * T_last_ref, half * T_last_ref,
                           T_last_ref, SE3d()};
  if (impl_->options.reversed_step_hypothesis) out.push_back(velocity.inverse() * T_last_ref);
  // The prediction turned by a·(i, j, k), (i, j, k) ∈ {−1, 0, 1}³ \ 0: single axes first,
  // then pairs, then triples (the header's order of likelihood); the wide ring after.
  for (const double a : {impl_->options.rotation_hypothesis_rad,
                         impl_->options.wide_rotation_hypothesis_rad}) {
    if (!(a > 0)) continue;
    for (int nonzero = 1; nonzero <= 3; ++nonzero)
      for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
          for (int k = -1; k <= 1; ++k) {
            if (std::abs(i) + std::abs(j) + std::abs(k) != nonzero) continue;
            Eigen::Matrix<double, 6, 1> xi;
            xi << 0, 0, 0, a * i, a * j, a * k;
            out.push_back(SE3d::exp(xi) * predicted);
          }
  }
  return out;
}

TrackingResult CoarseTracker::track(const ImagePyramid& frame, double exposure,
                                    const std::vector<SE3d>& hypotheses,
                                    const Eigen::Vector2d& affine_guess,
                                    double previous_rmse) const {
  TrackingResult best;
  if (!hasReference() || hypotheses.empty()) return best;
  const int levels = std::min<int>(impl_->reference->observations().size(), frame.numLevels());
  const Eigen::Vector2d start = impl_->toReferenceGauge(affine_guess, exposure);
  withResidualModel<void>(impl_->camera, [&](auto tag, const auto& model) {
    SE3d winning_hypothesis;
    const Impl::Pass plain = impl_->plainPass();
    best = impl_->tryHypotheses(tag, model, frame, exposure, levels, hypotheses, start,
                                previous_rmse, plain, &winning_hypothesis);
    // The header's retry on the dilated reference, for a frame no hypothesis tracked well
    // enough: its result is a hypothesis for the plain reference, adopted where it ends lower.
    if (impl_->options.dilated_retry && std::isfinite(previous_rmse) &&
        !impl_->goodEnough(best, previous_rmse)) {
      SE3d ignored;
      const Impl::Pass dilated{impl_->reference->dilatedObservations(model),
                               impl_->options.retry_max_iterations};
      const TrackingResult wide =
          impl_->tryHypotheses(tag, model, frame, exposure, levels, hypotheses, start,
                               previous_rmse, dilated, &ignored);
      best.dilated_retry = true;
      best.hypotheses_tried += wide.hypotheses_tried;
      if (wide.ok) {
        const TrackingResult again = impl_->tryHypotheses(
            tag, model, frame, exposure, levels, {wide.T_frame_ref}, start,
            std::numeric_limits<double>::infinity(), plain, &ignored);
        if (again.ok && (!best.ok || again.rmse < best.rmse)) {
          const int tried = best.hypotheses_tried + again.hypotheses_tried;
          best = again;
          best.hypotheses_tried = tried;
          best.dilated_retry = true;
          winning_hypothesis = wide.T_frame_ref;
        }
      }
    }
    // The header's second start: the finest level alone, from the winning hypothesis, when
    // coarse to fine lowered the finest-level error by less than `second_start_gain` of the
    // hypothesis' own.
    if (best.ok && impl_->options.finest_level_second_start && levels > 1) {
      std::array<double, 7> pose;
      winning_hypothesis.toParameters(pose.data());
      std::array<double, 2> affine = {start.x(), start.y()};
      const TrackingLevelSolve at_hypothesis =
          impl_->solveLevel(tag, model, 0, frame, exposure, pose.data(), affine.data(), false);
      if (best.rmse >= (1.0 - impl_->options.second_start_gain) * at_hypothesis.rmse) {
        const TrackingLevelSolve r =
            impl_->solveLevel(tag, model, 0, frame, exposure, pose.data(), affine.data(), true);
        const SE3d second = SE3d::fromParameters(pose.data());
        if (std::isfinite(r.rmse) && r.valid_fraction >= impl_->options.min_valid_fraction &&
            r.rmse < best.rmse &&
            impl_->rmsShiftBetween(model, best.T_frame_ref, second) >
                impl_->options.second_start_min_shift_px) {
          best.T_frame_ref = second;
          best.affine =
              impl_->fromReferenceGauge(Eigen::Vector2d(affine[0], affine[1]), exposure);
          best.level_rmse[0] = r.rmse;
          best.rmse = r.rmse;
          best.valid_fraction = r.valid_fraction;
        }
      }
    }
    if (best.ok) impl_->flow(tag, model, best.T_frame_ref, &best);
  });
  return best;
}

}  // namespace omnidso
