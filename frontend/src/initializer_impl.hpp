#pragma once
// Internal to the initialiser (initializer.hpp): the state behind the Initializer facade and
// the steps that act on it, one job per file:
//   initializer.cc         the facade: addFrame (the rotation search, the levels coarse to
//                          fine, the snap, the scale), the parallax, the state-based hooks;
//   initializer_levels.cc  one level's problem and its solve — by Ceres (the oracle) or
//                          natively (initializer_solver.hpp) — and the rotation search's
//                          costs.

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/frontend/initializer_level_patches.hpp>
#include <omnidso/frontend/initializer_solver.hpp>
#include <omnidso/frontend/model_dispatch.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <string>
#include <utility>
#include <vector>

namespace omnidso {

struct Initializer::Impl {
  Camera camera;
  Mask mask;
  InitializerOptions options;
  std::unique_ptr<PhotometricResidualFactory> factory;
  TaskPool* pool = nullptr;  // not owned; null: the calling thread alone
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
  // Per level, which points enter its problem (options.level_cell_px), for the current first
  // frame (levelMembers).
  std::vector<std::vector<char>> level_members;
  int frames_tried = 0;
  int snapped_at = -1;  // frames_tried when the parallax first sufficed; -1 before
  // The least error of a frame whose parallax was still below the snap's (+∞ before one):
  // the pair's own error floor (InitializerOptions::max_rmse_growth).
  double pre_snap_rmse = std::numeric_limits<double>::infinity();
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
    pre_snap_rmse = std::numeric_limits<double>::infinity();
  }

  // The acceptance bound on the photometric error (max_rmse, max_rmse_growth).
  double maxRmse() const {
    const double relative = options.max_rmse_growth * pre_snap_rmse;
    return std::isfinite(relative) ? std::max(options.max_rmse, relative) : options.max_rmse;
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

  LevelProblem buildLevel(int level, const ImagePyramid& frame, double exposure, bool snapped);

  // The native path's level (initializer_solver.hpp): the points buildLevel keeps (inside
  // the margin, valid at the current values), the same regularisers and prior.
  struct NativeLevel {
    std::unique_ptr<ceres::LossFunction> loss;
    std::vector<size_t> points;  // into pixels
    InitializerLevelProblem problem;
  };

  // One level: the RMS residual over valid pattern pixels, and the valid mask.
  InitializerLevelSolve solveLevel(int level, const ImagePyramid& frame, double exposure,
                                   bool snapped, std::vector<bool>* valid_points);

  static InitializerLevelSolve levelResult(const std::vector<std::pair<size_t, double>>& energies,
                                           InitializerLevelSolve out);

  NativeLevel buildNativeLevel(int level, const ImagePyramid& frame, double exposure,
                               bool snapped);

  // The patches of `level`, made once for the camera's model (model_dispatch.hpp).
  InitializerLevelPatchesBase& levelPatches(int level);

  template <template <typename> class M>
  std::unique_ptr<InitializerLevelPatchesBase> makePatches(ModelTag<M>, const M<double>& model,
                                                           int level) const;

  // Per point, whether it enters level `level`'s problem: the first point of each cell of
  // options.level_cell_px level pixels, in selection order (all on level 0, or with 0).
  const std::vector<char>& levelMembers(int level);

  double regularizerMean(bool snapped) const;

  // The cost of the level's problem — the points valid at candidates[0] — at every candidate
  // pose (+∞ where it cannot be evaluated); empty when no point is valid. The pose is left
  // at candidates[0]. least_only: a candidate's evaluation stops (+∞) once its sum exceeds
  // the least cost seen so far — candidates[0]'s, evaluated first, and its chunk's since
  // (initializerLevelCost's bound) —, which never stops the first of the least: the search's
  // choice is the same, the other costs are not.
  std::vector<double> candidateCosts(int level, const ImagePyramid& frame, double exposure,
                                     bool snapped, const std::vector<SE3d>& candidates,
                                     bool least_only = false);

  // The start of the coarsest level (header comment): the best, by cost, of every rotation
  // on a grid around each of `centres` (the constant-velocity prediction, then the last
  // solution) — steps of `rotation_search_step_px` at that level, converted to an angle
  // through the camera's resolution at the image centre. A fast turn moves the image further
  // than the alignment's basin (≈ 1–2 px at the coarsest level), and a sudden stop puts the
  // truth far from the prediction; the cost at the grid's nodes tells which basin to start
  // from.
  void searchRotationStart(int level, const ImagePyramid& frame, double exposure, bool snapped,
                           const std::vector<SE3d>& centres);

  // Angle between the bearings of the image centre and the pixel beside it.
  double radiansPerPixel() const;

  // Every level of `frame`, coarse to fine, from the current state: the finest level's RMS
  // residual, and `valid` its valid points.
  double solveAllLevels(int levels, const ImagePyramid& frame, double exposure, bool snapped,
                        std::vector<bool>* valid);

  // The snap's solve (options.snap_translation_starts): from the pre-snap state and, where
  // on, from the six pure translations; the state left at the solution kept.
  double solveAtSnap(int levels, const ImagePyramid& frame, double exposure,
                     std::vector<bool>* valid);

  struct Parallax {
    double px = 0.0;
    double deg = 0.0;
  };
  Parallax parallax(const std::vector<bool>& valid) const;

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
};

}  // namespace omnidso
