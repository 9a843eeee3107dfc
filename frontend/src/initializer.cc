#include <ceres/ceres.h>

#include <cmath>
#include <numeric>
#include <omnidso/backend/affine_prior.hpp>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/frontend/initializer_solver.hpp>
#include <omnidso/frontend/model_dispatch.hpp>
#include <omnidso/residuals/residual_pattern.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <sstream>

#include <omnidso/frontend/initializer_level_patches.hpp>

namespace omnidso {
namespace {

// r = √λ (d − d̄): keeps unobservable inverse distances together (header comment).
class InverseDistanceRegularizer final : public ceres::SizedCostFunction<1, 1> {
 public:
  InverseDistanceRegularizer(double sqrt_weight, double mean)
      : sqrt_weight_(sqrt_weight), mean_(mean) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    r[0] = sqrt_weight_ * (x[0][0] - mean_);
    if (J && J[0]) J[0][0] = sqrt_weight_;
    return true;
  }

 private:
  double sqrt_weight_, mean_;
};

// r = √(λ N) · t, t the frame's position in the first frame (pose parameters 4–6): before
// the snap, the motion is explained by rotation unless translation is clearly needed
// (header comment).
class TranslationRegularizer final : public ceres::SizedCostFunction<3, 7> {
 public:
  explicit TranslationRegularizer(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    for (int k = 0; k < 3; ++k) r[k] = sqrt_weight_ * x[0][4 + k];
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> j(J[0]);
      j.setZero();
      j.rightCols<3>().diagonal().setConstant(sqrt_weight_);
    }
    return true;
  }

 private:
  double sqrt_weight_;
};

}  // namespace

struct Initializer::Impl {
  Camera camera;
  Mask mask;
  InitializerOptions options;
  std::unique_ptr<PhotometricResidualFactory> factory;
  std::shared_ptr<const ImagePyramid> first;
  double first_exposure = 1.0;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<double> inverse_distances;
  std::array<double, 7> pose{};  // T_world_frame with the first frame at the identity
  std::array<double, 7> pose_before{};  // the solution of the frame before the last
  std::array<double, 2> affine{};
  std::array<double, 7> host_pose{};
  std::array<double, 2> host_affine{};
  Eigen::VectorXd intrinsics;
  SE3Manifold manifold;
  // The native path's patches per level, for the current first frame (buildNativeLevel).
  std::vector<std::unique_ptr<InitializerLevelPatchesBase>> level_patches;
  int frames_tried = 0;
  int snapped_at = -1;  // frames_tried when the parallax first sufficed; -1 before
  std::string status = "no frame yet";

  Impl(const Camera& c, const Mask& m, InitializerOptions o)
      : camera(c),
        mask(m),
        options(std::move(o)),
        factory(PhotometricResidualFactory::forModel(c.modelName())),
        intrinsics(c.params()) {}

  void reset() {
    SE3d().toParameters(pose.data());
    SE3d().toParameters(pose_before.data());
    SE3d().toParameters(host_pose.data());
    affine = {0.0, 0.0};
    host_affine = {0.0, 0.0};
    frames_tried = 0;
    snapped_at = -1;
  }

  // One level's problem: a photometric residual for every point that projects validly from
  // the current pose, its distance regulariser, and the frame's affine prior. Before the snap
  // the distances are tied to 1 and the translation to 0 (fixing the scale the translation
  // penalty would otherwise shrink away); after it, the distances to their mean only.
  struct LevelProblem {
    std::unique_ptr<ceres::LossFunction> loss;
    std::unique_ptr<ceres::Problem> problem;
    std::vector<std::pair<size_t, ceres::ResidualBlockId>> blocks;
  };

  LevelProblem buildLevel(int level, const ImagePyramid& frame, double exposure, bool snapped) {
    const double lambda = snapped ? options.regularizer_weight : options.pre_snap_regularizer_weight;
    const ImageF& host_image = first->level(level);
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    LevelProblem lp;
    lp.problem = std::make_unique<ceres::Problem>(po);
    lp.loss.reset(makePhotometricLoss(kWindowPatternSize, options.huber_threshold));
    ceres::Problem& problem = *lp.problem;
    problem.AddParameterBlock(pose.data(), 7, &manifold);
    problem.AddParameterBlock(host_pose.data(), 7, &manifold);
    problem.SetParameterBlockConstant(host_pose.data());
    problem.AddParameterBlock(host_affine.data(), 2);
    problem.SetParameterBlockConstant(host_affine.data());
    problem.AddParameterBlock(affine.data(), 2);
    if (options.affine_prior_weight_a > 0 || options.affine_prior_weight_b > 0)
      problem.AddResidualBlock(new AffinePrior(Eigen::Vector2d::Zero(), options.affine_prior_weight_a,
                                               options.affine_prior_weight_b),
                               nullptr, affine.data());
    problem.AddParameterBlock(intrinsics.data(), static_cast<int>(intrinsics.size()));
    problem.SetParameterBlockConstant(intrinsics.data());
    const double mean_d = regularizerMean(snapped);
    for (size_t i = 0; i < pixels.size(); ++i) {
      const Eigen::Vector2d p(pixelToLevel(pixels[i].x(), level), pixelToLevel(pixels[i].y(), level));
      if (!insideMargin(p, host_image)) continue;
      WindowObservation obs;
      obs.host = makeHostPatch<kWindowPatternSize>(host_image, first->gradients(level), p);
      obs.target_image = &frame.level(level);
      obs.target_content = frame.content(level);
      obs.host_exposure = first_exposure;
      obs.target_exposure = exposure;
      obs.level = level;
      double* params[] = {host_pose.data(), pose.data(), &inverse_distances[i],
                          host_affine.data(), affine.data(), intrinsics.data()};
      if (factory->status(obs, params) != PhotometricStatus::kValid) continue;
      lp.blocks.emplace_back(
          i, problem.AddResidualBlock(
                 new OutOfBoundsPenalty(factory->makeCost(DifferentiationMode::kAnalytic, obs),
                                        kDsoOutlierEnergyPerPixel * kWindowPatternSize),
                 lp.loss.get(), std::vector<double*>(params, params + 6)));
      problem.AddResidualBlock(
          new InverseDistanceRegularizer(std::sqrt(lambda), mean_d), nullptr,
          &inverse_distances[i]);
    }
    if (!snapped && options.pre_snap_translation_penalty && !lp.blocks.empty())
      problem.AddResidualBlock(
          new TranslationRegularizer(std::sqrt(lambda * static_cast<double>(lp.blocks.size()))),
          nullptr, pose.data());
    return lp;
  }

  // One level: the RMS residual over valid pattern pixels, and the valid mask.
  InitializerLevelSolve solveLevel(int level, const ImagePyramid& frame, double exposure,
                                   bool snapped, std::vector<bool>* valid_points) {
    valid_points->assign(pixels.size(), false);
    InitializerLevelSolve out;
    std::vector<std::pair<size_t, double>> energies;  // per point of the problem
    if (options.native_solver) {
      NativeLevel nl = buildNativeLevel(level, frame, exposure, snapped);
      if (nl.points.empty()) return levelResult(energies, out);
      std::vector<double> d;
      for (size_t i : nl.points) d.push_back(inverse_distances[i]);
      InitializerSolverOptions so;
      so.max_num_iterations = options.max_iterations_per_level;
      const InitializerSolverSummary summary =
          solveInitializerLevel(nl.problem, so, pose.data(), affine.data(), &d);
      out.iterations = summary.iterations;
      for (size_t k = 0; k < nl.points.size(); ++k) {
        inverse_distances[nl.points[k]] = d[k];  // unchanged after a failure, as with Ceres
        energies.emplace_back(nl.points[k], summary.energies[k]);
      }
    } else {
      LevelProblem lp = buildLevel(level, frame, exposure, snapped);
      if (lp.blocks.empty()) return levelResult(energies, out);
      ceres::Solver::Options so;
      auto* ordering = new ceres::ParameterBlockOrdering;
      for (const auto& [i, id] : lp.blocks) ordering->AddElementToGroup(&inverse_distances[i], 0);
      // One group each: Ceres orders a group's blocks by address, which would make the
      // reduced system's column order (and its last bits) depend on the heap layout.
      int group = 1;
      for (double* b : {pose.data(), host_pose.data(), host_affine.data(), affine.data(),
                        intrinsics.data()})
        ordering->AddElementToGroup(b, group++);
      so.linear_solver_ordering.reset(ordering);
      so.linear_solver_type = ceres::DENSE_SCHUR;
      so.max_num_iterations = options.max_iterations_per_level;
      so.logging_type = ceres::SILENT;
      ceres::Solver::Summary summary;
      ceres::Solve(so, lp.problem.get(), &summary);
      out.iterations = static_cast<int>(summary.iterations.size()) - 1;
      // The wrapped residual's energy; infinite where it is out of bounds or its inverse
      // distance went negative (it only carried the penalty then).
      for (const auto& [i, id] : lp.blocks) energies.emplace_back(i, rawEnergy(*lp.problem, id));
    }
    for (const auto& [i, energy] : energies) (*valid_points)[i] = std::isfinite(energy);
    return levelResult(energies, out);
  }

  static InitializerLevelSolve levelResult(const std::vector<std::pair<size_t, double>>& energies,
                                           InitializerLevelSolve out) {
    double sum = 0.0;
    int n = 0;
    out.num_points = static_cast<int>(energies.size());
    for (const auto& [i, energy] : energies) {
      if (!std::isfinite(energy)) continue;
      ++out.num_valid;
      sum += energy;
      n += kWindowPatternSize;
    }
    out.rmse = n ? std::sqrt(sum / n) : std::numeric_limits<double>::infinity();
    return out;
  }

  // The native path's level (initializer_solver.hpp): the points buildLevel keeps (inside
  // the margin, valid at the current values), the same regularisers and prior.
  struct NativeLevel {
    std::unique_ptr<ceres::LossFunction> loss;
    std::vector<size_t> points;  // into pixels
    InitializerLevelProblem problem;
  };

  NativeLevel buildNativeLevel(int level, const ImagePyramid& frame, double exposure,
                               bool snapped) {
    NativeLevel nl;
    InitializerLevelPatchesBase& patches = levelPatches(level);
    patches.setFrame(frame.level(level), frame.content(level), exposure);
    patches.setPoint(pose.data(), affine.data());
    const ImageF& host_image = first->level(level);
    for (size_t i = 0; i < pixels.size(); ++i) {
      const Eigen::Vector2d p(pixelToLevel(pixels[i].x(), level), pixelToLevel(pixels[i].y(), level));
      if (!insideMargin(p, host_image)) continue;
      if (patches.addIfValid(makeHostPatch<kWindowPatternSize>(host_image, first->gradients(level), p),
                             inverse_distances[i]))
        nl.points.push_back(i);
    }
    const double lambda = snapped ? options.regularizer_weight : options.pre_snap_regularizer_weight;
    nl.loss.reset(makePhotometricLoss(kWindowPatternSize, options.huber_threshold));
    InitializerLevelProblem& p = nl.problem;
    p.patches = &patches;
    p.loss = nl.loss.get();
    p.invalid_residual = std::sqrt(kDsoOutlierEnergyPerPixel * kWindowPatternSize / kWindowPatternSize);
    p.regularizer_sqrt_weight = std::sqrt(lambda);
    p.regularizer_mean = regularizerMean(snapped);
    if (!snapped && options.pre_snap_translation_penalty && !nl.points.empty())
      p.translation_sqrt_weight = std::sqrt(lambda * static_cast<double>(nl.points.size()));
    p.affine_prior_weight_a = options.affine_prior_weight_a;
    p.affine_prior_weight_b = options.affine_prior_weight_b;
    return nl;
  }

  // The patches of `level`, made once for the camera's model (model_dispatch.hpp).
  InitializerLevelPatchesBase& levelPatches(int level) {
    if (level_patches.size() <= static_cast<size_t>(level)) level_patches.resize(level + 1);
    std::unique_ptr<InitializerLevelPatchesBase>& patches = level_patches[static_cast<size_t>(level)];
    if (!patches)
      patches = withResidualModel<std::unique_ptr<InitializerLevelPatchesBase>>(
          camera, [&](auto tag, const auto& model) { return makePatches(tag, model, level); });
    return *patches;
  }

  template <template <typename> class M>
  std::unique_ptr<InitializerLevelPatchesBase> makePatches(ModelTag<M>, const M<double>& model,
                                                           int level) const {
    typename M<double>::VecN params = model.params();
    scaleIntrinsicsToLevel(params, level);
    return std::make_unique<InitializerLevelPatches<M>>(M<double>(params), first_exposure,
                                                        host_pose.data(), host_affine.data(),
                                                        pixels.size());
  }

  static bool insideMargin(const Eigen::Vector2d& p, const ImageF& image) {
    const double margin = patternRadius<kWindowPatternSize>() + 1.0;
    return p.x() >= margin && p.y() >= margin && p.x() <= image.width() - 1 - margin &&
           p.y() <= image.height() - 1 - margin;
  }

  double regularizerMean(bool snapped) const {
    return snapped ? std::accumulate(inverse_distances.begin(), inverse_distances.end(), 0.0) /
                         std::max<size_t>(1, inverse_distances.size())
                   : 1.0;
  }

  // The start of the coarsest level (header comment): the best, by cost, of every rotation
  // on a grid around each of `centres` (the constant-velocity prediction, then the last
  // solution) — steps of `rotation_search_step_px` at that level, converted to an angle
  // through the camera's resolution at the image centre. A fast turn moves the image further
  // than the alignment's basin (≈ 1–2 px at the coarsest level), and a sudden stop puts the
  // truth far from the prediction; the cost at the grid's nodes tells which basin to start
  // from.
  void searchRotationStart(int level, const ImagePyramid& frame, double exposure, bool snapped,
                           const std::vector<SE3d>& centres) {
    const int half = options.rotation_search_half_width;
    if (half <= 0 || !(options.rotation_search_step_px > 0) || centres.empty()) return;
    const double step = options.rotation_search_step_px * std::ldexp(1.0, level) * radiansPerPixel();
    if (!(step > 0)) return;
    std::vector<SE3d> candidates = {centres.front()};  // first: the prediction wins ties
    for (const SE3d& centre : centres)
      for (int x = -half; x <= half; ++x)
        for (int y = -half; y <= half; ++y)
          for (int z = -half; z <= half; ++z) {
            Eigen::Matrix<double, 6, 1> xi;
            xi << 0, 0, 0, x * step, y * step, z * step;
            candidates.push_back(centre * SE3d::exp(xi));  // turned in the frame
          }
    const std::vector<double> costs = candidateCosts(level, frame, exposure, snapped, candidates);
    size_t best = 0;
    for (size_t k = 1; k < costs.size(); ++k)
      if (costs[k] < costs[best]) best = k;
    candidates[best].toParameters(pose.data());
  }

  // The cost of the level's problem — the points valid at candidates[0] — at every candidate
  // pose (+∞ where it cannot be evaluated); empty when no point is valid. The pose is left
  // at candidates[0].
  std::vector<double> candidateCosts(int level, const ImagePyramid& frame, double exposure,
                                     bool snapped, const std::vector<SE3d>& candidates) {
    candidates.front().toParameters(pose.data());
    std::vector<double> costs;
    if (options.native_solver) {
      const NativeLevel nl = buildNativeLevel(level, frame, exposure, snapped);
      std::vector<double> d;
      for (size_t i : nl.points) d.push_back(inverse_distances[i]);
      std::array<double, 7> candidate_pose;
      for (size_t k = 0; k < candidates.size() && !nl.points.empty(); ++k) {
        candidates[k].toParameters(candidate_pose.data());
        costs.push_back(initializerLevelCost(nl.problem, candidate_pose.data(), affine.data(), d));
      }
    } else {
      const LevelProblem lp = buildLevel(level, frame, exposure, snapped);
      for (size_t k = 0; k < candidates.size() && !lp.blocks.empty(); ++k) {
        candidates[k].toParameters(pose.data());
        double cost = 0.0;
        costs.push_back(lp.problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr,
                                             nullptr, nullptr)
                            ? cost
                            : std::numeric_limits<double>::infinity());
      }
    }
    candidates.front().toParameters(pose.data());
    return costs;
  }

  // Runs `work` on `state` in place of the initialiser's own, restored afterwards.
  template <typename Work>
  auto withState(InitializerState* state, Work&& work) {
    if (state->inverse_distances.size() != pixels.size())
      throw Error("Initializer: a state needs one inverse distance per point");
    const auto saved_pose = pose;
    const auto saved_affine = affine;
    const std::vector<double> saved_distances = inverse_distances;
    state->T_world_frame.toParameters(pose.data());
    affine = {state->affine.x(), state->affine.y()};
    inverse_distances = state->inverse_distances;
    const auto result = work();
    state->T_world_frame = SE3d::fromParameters(pose.data());
    state->affine = Eigen::Vector2d(affine[0], affine[1]);
    state->inverse_distances = inverse_distances;
    pose = saved_pose;
    affine = saved_affine;
    inverse_distances = saved_distances;
    return result;
  }

  // Angle between the bearings of the image centre and the pixel beside it.
  double radiansPerPixel() const {
    const Eigen::Vector2d c(0.5 * (camera.width() - 1), 0.5 * (camera.height() - 1));
    Eigen::Vector3d a, b;
    if (!camera.unproject(c, a) || !camera.unproject(c + Eigen::Vector2d(1.0, 0.0), b)) return 0.0;
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
  }

  double parallax(const std::vector<bool>& valid) const {
    const SE3d T = SE3d::fromParameters(pose.data());
    double sum = 0.0;
    int n = 0;
    for (size_t i = 0; i < pixels.size(); ++i) {
      if (!valid[i]) continue;
      Eigen::Vector3d b;
      Eigen::Vector2d u;
      // T_world_frame = T_first_frame: the point in the frame is T⁻¹ x; translation only.
      const SE3d T_frame_first = T.inverse();
      if (!camera.unproject(pixels[i], b) ||
          !camera.project(b + inverse_distances[i] * T_frame_first.translation(), u))
        continue;
      sum += (u - pixels[i]).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(sum / n) : 0.0;
  }
};

Initializer::Initializer(const Camera& camera, const Mask& mask, InitializerOptions options)
    : impl_(std::make_unique<Impl>(camera, mask, std::move(options))) {}

Initializer::~Initializer() = default;

bool Initializer::hasFirstFrame() const { return impl_->first != nullptr; }
int Initializer::numFramesTried() const { return impl_->frames_tried; }
const std::string& Initializer::status() const { return impl_->status; }

void Initializer::setFirstFrame(std::shared_ptr<const ImagePyramid> pyramid, double exposure) {
  impl_->first = std::move(pyramid);
  impl_->first_exposure = exposure;
  impl_->reset();
  impl_->pixels.clear();
  impl_->inverse_distances.clear();
  impl_->level_patches.clear();  // their host exposure and capacity are the first frame's
  for (const SelectedPixel& p : selectPixels(*impl_->first, impl_->mask, impl_->options.selection)) {
    impl_->pixels.push_back(p.pixel.cast<double>());
    impl_->inverse_distances.push_back(1.0);
  }
  impl_->status = "first frame set with " + std::to_string(impl_->pixels.size()) + " points";
}

InitializerState Initializer::state() const {
  return {SE3d::fromParameters(impl_->pose.data()),
          Eigen::Vector2d(impl_->affine[0], impl_->affine[1]), impl_->inverse_distances};
}

InitializerLevelSolve Initializer::solveLevel(const ImagePyramid& frame, double exposure,
                                              int level, bool snapped, InitializerState* state) {
  std::vector<bool> valid;
  return impl_->withState(state, [&] {
    return impl_->solveLevel(level, frame, exposure, snapped, &valid);
  });
}

std::vector<double> Initializer::rotationSearchCosts(const ImagePyramid& frame, double exposure,
                                                     int level, bool snapped,
                                                     const InitializerState& state,
                                                     const std::vector<SE3d>& candidates) {
  if (candidates.empty()) return {};
  InitializerState copy = state;
  return impl_->withState(&copy, [&] {
    return impl_->candidateCosts(level, frame, exposure, snapped, candidates);
  });
}

InitializationResult Initializer::addFrame(const ImagePyramid& frame, double exposure) {
  InitializationResult result;
  if (!hasFirstFrame()) throw Error("Initializer::addFrame before setFirstFrame");
  const int frames_tried_before_this = impl_->frames_tried++;
  const int levels = std::min({impl_->options.num_levels, frame.numLevels(),
                               impl_->first->numLevels()});
  const InitializerOptions& o = impl_->options;
  const double min_parallax =
      o.min_parallax_px > 0 ? o.min_parallax_px : 0.01 * (impl_->camera.width() + impl_->camera.height());
  std::vector<bool> valid;
  double rmse = std::numeric_limits<double>::infinity();
  auto solveAllLevels = [&](bool snapped) {
    for (int level = levels - 1; level >= 0; --level)
      rmse = impl_->solveLevel(level, frame, exposure, snapped, &valid).rmse;
  };
  const bool snapped_before = impl_->snapped_at >= 0;
  {  // start: the rotation search around the constant-velocity prediction and the last pose
    const SE3d last = SE3d::fromParameters(impl_->pose.data());
    const SE3d before = SE3d::fromParameters(impl_->pose_before.data());
    const SE3d predicted = last * (before.inverse() * last);
    last.toParameters(impl_->pose_before.data());
    predicted.toParameters(impl_->pose.data());
    std::vector<SE3d> centres = {predicted};
    if (frames_tried_before_this > 0) centres.push_back(last);  // else both are the identity
    impl_->searchRotationStart(levels - 1, frame, exposure, snapped_before, centres);
  }
  solveAllLevels(snapped_before);
  double parallax = impl_->parallax(valid);
  if (!snapped_before && parallax >= min_parallax) {
    impl_->snapped_at = impl_->frames_tried;
    solveAllLevels(true);
    parallax = impl_->parallax(valid);
  }
  const int num_valid = static_cast<int>(std::count(valid.begin(), valid.end(), true));
  result.parallax_px = parallax;
  result.rmse = rmse;
  std::ostringstream status;
  status << "after " << impl_->frames_tried << " frames: parallax " << parallax << " px of the "
         << min_parallax << " px needed, photometric error " << rmse << " (at most "
         << impl_->options.max_rmse << "), " << num_valid << " points";
  if (impl_->snapped_at >= 0) status << ", snapped at frame " << impl_->snapped_at;
  impl_->status = status.str();
  if (impl_->snapped_at < 0 || impl_->frames_tried < impl_->snapped_at + o.frames_after_snap ||
      !(parallax >= min_parallax) || !(rmse <= o.max_rmse) || num_valid < o.min_points)
    return result;

  // Scale: mean inverse distance 1 (d' = d/m, t' = m t).
  double mean = 0.0;
  for (size_t i = 0; i < valid.size(); ++i)
    if (valid[i]) mean += impl_->inverse_distances[i];
  mean /= num_valid;
  if (!(mean > 0.0)) return result;
  SE3d T_world_frame = SE3d::fromParameters(impl_->pose.data());
  T_world_frame.translation() *= mean;
  result.T_frame_first = T_world_frame.inverse();
  result.frame_affine = Eigen::Vector2d(impl_->affine[0], impl_->affine[1]);
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    result.pixels.push_back(impl_->pixels[i]);
    result.inverse_distances.push_back(impl_->inverse_distances[i] / mean);
  }
  result.done = true;
  return result;
}

}  // namespace omnidso
