// The initialiser's levels (initializer_impl.hpp): one level's problem — photometric
// patches, the distance regularisers, the translation tie before the snap, the affine prior
// (initializer.hpp) — solved by Ceres or by the native solve (initializer_solver.hpp), and
// the rotation search's costs by either.
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <utility>
#include <omnidso/backend/affine_prior.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

#include "initializer_impl.hpp"

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

Initializer::Impl::LevelProblem Initializer::Impl::buildLevel(int level, const ImagePyramid& frame,
                                                              double exposure, bool snapped) {
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
  const std::vector<char>& members = levelMembers(level);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const Eigen::Vector2d p(pixelToLevel(pixels[i].x(), level), pixelToLevel(pixels[i].y(), level));
    if (!members[i] ||
        !hostPatchFits<kWindowPatternSize>(host_image, p, options.pattern_spread))
      continue;
    WindowObservation obs;
    obs.host = makeHostPatch<kWindowPatternSize>(host_image, first->gradients(level), p,
                                                 kDsoGradientWeightC, first->encodingSlope(level),
                                                 options.pattern_spread);
    obs.target_image = &frame.level(level);
    obs.target_content = frame.content(level);
    obs.gradient = imageGradient(options.central_difference_gradients);
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

InitializerLevelSolve Initializer::Impl::solveLevel(int level, const ImagePyramid& frame,
                                                    double exposure, bool snapped,
                                                    std::vector<bool>* valid_points) {
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

InitializerLevelSolve Initializer::Impl::levelResult(
    const std::vector<std::pair<size_t, double>>& energies, InitializerLevelSolve out) {
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

Initializer::Impl::NativeLevel Initializer::Impl::buildNativeLevel(int level,
                                                                   const ImagePyramid& frame,
                                                                   double exposure, bool snapped) {
  NativeLevel nl;
  InitializerLevelPatchesBase& patches = levelPatches(level);
  patches.setFrame(frame.level(level), frame.content(level), exposure);
  patches.setPoint(pose.data(), affine.data());
  const ImageF& host_image = first->level(level);
  const std::vector<char>& members = levelMembers(level);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const Eigen::Vector2d p(pixelToLevel(pixels[i].x(), level), pixelToLevel(pixels[i].y(), level));
    if (!members[i] ||
        !hostPatchFits<kWindowPatternSize>(host_image, p, options.pattern_spread))
      continue;
    if (patches.addIfValid(makeHostPatch<kWindowPatternSize>(host_image, first->gradients(level), p,
                                                             kDsoGradientWeightC,
                                                             first->encodingSlope(level),
                                                             options.pattern_spread),
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

template <template <typename> class M>
std::unique_ptr<InitializerLevelPatchesBase> Initializer::Impl::makePatches(ModelTag<M>,
                                                                            const M<double>& model,
                                                                            int level) const {
  typename M<double>::VecN params = model.params();
  scaleIntrinsicsToLevel(params, level);
  const ImageGradient gradient = imageGradient(options.central_difference_gradients);
  return std::make_unique<InitializerLevelPatches<M>>(M<double>(params), first_exposure,
                                                      host_pose.data(), host_affine.data(),
                                                      pixels.size(), gradient);
}

InitializerLevelPatchesBase& Initializer::Impl::levelPatches(int level) {
  if (level_patches.size() <= static_cast<size_t>(level)) level_patches.resize(level + 1);
  std::unique_ptr<InitializerLevelPatchesBase>& patches = level_patches[static_cast<size_t>(level)];
  if (!patches)
    patches = withResidualModel<std::unique_ptr<InitializerLevelPatchesBase>>(
        camera, [&](auto tag, const auto& model) { return makePatches(tag, model, level); });
  return *patches;
}

const std::vector<char>& Initializer::Impl::levelMembers(int level) {
  if (level_members.size() <= static_cast<size_t>(level)) level_members.resize(level + 1);
  std::vector<char>& members = level_members[static_cast<size_t>(level)];
  if (members.size() == pixels.size()) return members;
  const double cell = options.level_cell_px;
  members.assign(pixels.size(), 1);
  if (level == 0 || !(cell > 0)) return members;
  std::set<std::pair<long, long>> taken;
  for (size_t i = 0; i < pixels.size(); ++i) {
    const long u = static_cast<long>(std::floor(pixelToLevel(pixels[i].x(), level) / cell));
    const long v = static_cast<long>(std::floor(pixelToLevel(pixels[i].y(), level) / cell));
    members[i] = taken.emplace(u, v).second;
  }
  return members;
}

double Initializer::Impl::regularizerMean(bool snapped) const {
  return snapped ? std::accumulate(inverse_distances.begin(), inverse_distances.end(), 0.0) /
                       std::max<size_t>(1, inverse_distances.size())
                 : 1.0;
}

std::vector<double> Initializer::Impl::candidateCosts(int level, const ImagePyramid& frame,
                                                      double exposure, bool snapped,
                                                      const std::vector<SE3d>& candidates,
                                                      bool least_only) {
  candidates.front().toParameters(pose.data());
  std::vector<double> costs;
  if (options.native_solver) {
    const NativeLevel nl = buildNativeLevel(level, frame, exposure, snapped);
    std::vector<double> d;
    for (size_t i : nl.points) d.push_back(inverse_distances[i]);
    // candidates[0] (the prediction, usually near the least) first, on the calling thread:
    // with least_only its cost bounds every chunk from the start. Then one contiguous chunk
    // of the others per compute thread, each with its own copy of the patches (setPoint keeps
    // the frame state in them), copied before any chunk runs: every cost is the same
    // evaluation, in the same order of operations, whatever the thread count. A chunk that
    // started from no bound computed its first candidates in full: two chunks did more work
    // than one (D1's initialisation slower with two compute threads than with one).
    if (nl.points.empty()) return costs;
    costs.resize(candidates.size());
    costs[0] = initializerLevelCost(nl.problem, pose.data(), affine.data(), d,
                                    std::numeric_limits<double>::infinity());
    const int n = static_cast<int>(costs.size()) - 1;  // the others, from index 1
    const int chunks = std::min(n, pool ? pool->numThreads() : 1);
    std::vector<std::unique_ptr<InitializerPatches>> copies;
    for (int c = 1; c < chunks; ++c) copies.push_back(nl.problem.patches->clone());
    runTasks(pool, chunks, [&](int c) {
      InitializerLevelProblem problem = nl.problem;
      if (c > 0) problem.patches = copies[static_cast<size_t>(c - 1)].get();
      std::array<double, 7> candidate_pose;
      double least = costs[0];
      for (int k = 1 + n * c / chunks; k < 1 + n * (c + 1) / chunks; ++k) {
        candidates[k].toParameters(candidate_pose.data());
        costs[k] = initializerLevelCost(problem, candidate_pose.data(), affine.data(), d,
                                        least_only ? least : std::numeric_limits<double>::infinity());
        least = std::min(least, costs[k]);
      }
    });
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

}  // namespace omnidso
