#pragma once
// Two-frame photometric initialisation, coarse to fine (DSO's coarse initialiser; paper
// Sec. V): candidate pixels of the first frame start at inverse distance 1; every following
// frame is aligned to the first by jointly optimising the relative pose, the frame's affine
// brightness and every point's inverse distance — photometric residuals (eq. 5–7), one
// problem per pyramid level, coarse to fine, starting from a rotation search (below), solved
// natively (initializer_solver.hpp) or by Ceres (InitializerOptions::native_solver).
// The inverse distances are regularised,
//   r_reg = √λ · (d − d̄),
// strongly (λ = pre_snap_regularizer_weight, d̄ = 1, and the translation too:
// r_t = √(λ N) · t over the N points, DSO's α energy) while the baseline is too small to
// observe them: with a nearly still or purely rotating camera, free distances otherwise fit
// noise and aliasing and drag the pose away (the error grows frame after frame), and a free
// translation mimics a rotation through a narrow lens. Once the RMS pixel shift the
// translation alone causes (parallax) exceeds `min_parallax_px` and the RMS angle it turns
// the points' rays by (the triangulation angle, ∠(b, b + d t)) exceeds `min_parallax_deg`,
// the initialiser "snaps" (as DSO's does): λ drops to `regularizer_weight` with d̄ the mean
// inverse distance and the translation free, the frame is solved again (from the pre-snap pose
// and from six pure translations: snap_translation_starts), and `frames_after_snap` more
// frames refine the distances on a growing baseline.
// Start of each frame: the coarsest level begins at the lowest-cost node of a rotation grid
// around the constant-velocity prediction and around the last pose (rotation_search_*): a
// fast hand-held swing displaces the coarsest level beyond the alignment's basin.
// It succeeds when, after those, the error is small enough (max_rmse, max_rmse_growth: within
// a bound referred to the pair's own error before the snap); the scale is then set so that
// the mean inverse distance is 1. With a camera standing still it never succeeds, and says
// so (status()).

#include <Eigen/Core>
#include <memory>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/residuals/photometric_residual.hpp>
#include <string>
#include <vector>

namespace omnidso {

struct InitializerOptions {
  int pattern_spread = 1;  // OdometryOptions::pattern_spread
  // The image gradient in the Jacobians: false, the bilinear interpolant's derivative; true,
  // central differences blended bilinearly (DSO's; core/interpolation.hpp).
  bool central_difference_gradients = false;
  int num_levels = 5;
  int max_iterations_per_level = 8;
  double regularizer_weight = 50.0;    // λ after the snap, intensity² per (inverse distance)²
  double pre_snap_regularizer_weight = 5000.0;  // λ before it
  bool pre_snap_translation_penalty = true;     // r_t = √(λ N) t before the snap
  // affine_prior.hpp, as the tracker's and the window's: with calibrated photometry a free
  // [a, b] trades contrast against geometry while the alignment is still far off.
  double affine_prior_weight_a = 1e8;
  double affine_prior_weight_b = 1e6;
  // The coarsest level starts from the best of (2h+1)³ rotations of the constant-velocity
  // prediction, `rotation_search_step_px` apart at that level; h = 0 switches it off.
  int rotation_search_half_width = 2;
  double rotation_search_step_px = 1.5;
  // On level L ≥ 1 a point enters the level's problem (and the rotation search) only when no
  // earlier point of the first frame's selection falls in the same cell of this many level-L
  // pixels: the ≈ 2 000 level-0 points crowd a coarse level — two and more per pixel of a
  // 30 × 30 level 4 — where their patterns sample the same pixels. 0 (the default): every
  // point on every level. 1 made D1's initialisation 0.6× as long, but the pinhole crop's
  // median error was higher in 7 of 8 sequences (docs/performance.md, "Native point
  // marginalisation; …"): a speed setting, not the default.
  double level_cell_px = 0.0;
  int frames_after_snap = 0;
  // At the snap, besides the solve from the pre-snap pose, one from each pure translation
  // t = ±|t_pre| e_k (k = x, y, z; identity rotation, the pre-snap distances and affine),
  // the lowest error kept if below snap_translation_start_gain × the default's. Before the
  // snap the translation is penalised, so a narrow view's shift across it is read as a turn;
  // the pre-snap pose is then one end of the rotation–translation ambiguity, and the snap's
  // solve can stay in its basin. On the 10 Hz holdout path H10 (a 480-pixel pinhole, f = 240,
  // moving 0.26 m back per frame; docs/performance.md, "The snap's translation starts") the
  // default kept a 4–8° pitch error at a photometric error of 6.5, the axial start reached
  // 3.2. The gain keeps a start that is merely as good from switching a solution that was
  // right: where the errors tie (0.994× on the holdout render H7) which start wins is chance.
  // Right starts were clearly lower: 0.49× (H10), and 0.90× on a car-like render (a 620 × 188
  // pinhole strip driving 0.25 m per frame at 10 Hz, where 0.8 kept a 5.6° yaw error and the
  // run lost 99 % of its scale, 17–22 % of the path; 0.95: 0.024–0.041 %, docs/performance.md,
  // "A car-like camera"). Only where the default's error is within the acceptance bound
  // (max_rmse, max_rmse_growth): above it the alignment is lost, and the parallax that
  // triggered the snap with it.
  bool snap_translation_starts = true;
  double snap_translation_start_gain = 0.95;
  double min_parallax_px = 0.0;        // 0: use 0.01 · (w + h)
  // The pixel criterion alone sets the distances' precision in pixels, the same for every
  // lens. A narrow view needs more: with the rotation taking the mean flow, its tracker reads
  // the translation from the spread of the distances, so noise in them shortens the steps
  // (errors in the variables). On a sharp 90° pinhole render of D2's path the pixel criterion
  // snapped at a 2.5° angle and the first keyframes turned up to 1.3× too far (0.68 % of the
  // path); at 5° it read 0.010–0.018 % over three seeds (docs/performance.md, "The
  // triangulation angle at the snap"). On the fisheyes the snap comes 0–3 frames later (D1,
  // hovering near its start: 19; room185: 3), the full image as accurate or more so.
  // 0: pixels only.
  double min_parallax_deg = 5.0;
  // The snap's own triangulation angle: the translation is freed (and the distances loosened)
  // once the pixel criterion and this angle are met; the initialiser accepts only once
  // min_parallax_deg is met as well, refining the snapped problem frame after frame until
  // then. −1: min_parallax_deg (snap and acceptance on the same frame).
  double snap_parallax_deg = -1.0;
  // The acceptance bound on the photometric error (intensity units per residual pixel):
  //   max(max_rmse, max_rmse_growth · e₀),
  // e₀ the least error of the frames aligned before the snap (their parallax short of it);
  // without such a frame, max_rmse alone. An absolute bound reads the scene as much as the
  // alignment: noise, texture finer than the pattern and slanted surfaces sheared by the step
  // set a right pair's error. Through a car-like 620 × 188 strip driving 0.3 m a frame past
  // fine texture, right alignments read 18–25 from the first frame on, and the initialiser
  // accepted none for 127 of 160 frames (docs/performance.md, "The initialiser's error
  // bound"). Before the snap the baseline is short and the frame is aligned by a rotation with
  // the distances held: its error is the pair's floor, and a right alignment grows from it by
  // what the longer baseline deforms until acceptance — where that floor was 9–19 (four
  // car-like renders, a blurred one) the accepted error was 0.95–1.41 e₀; where it was
  // 1.3–6.4 (the development set, the held-out fisheyes) 0.67–3.7 e₀, under max_rmse. A first
  // step that already snaps gives no floor: a swing the alignment lost can read as a 14°
  // triangulation angle on frame 1 (WaitsWhenNoPointProjectsAnyMore). Also where the snap
  // tries its translation starts (snap_translation_starts). max_rmse_growth 0: max_rmse alone.
  double max_rmse = 15.0;
  double max_rmse_growth = 1.5;
  int min_points = 50;
  int max_frames = 60;                 // give up (and restart from a newer frame) after this
  double huber_threshold = 9.0;
  // Each level and the rotation search's costs by the native solve (initializer_solver.hpp:
  // the same Levenberg–Marquardt as ceres::Solve, the points eliminated by the Schur
  // complement) instead of a ceres::Problem per frame, level and hypothesis. Setting
  // `initializer.native_solver`; false keeps the Ceres path (the oracle).
  bool native_solver = true;
  PixelSelectorOptions selection;
};

// What addFrame solves, from outside (the tests that hold the native solve against Ceres's).
struct InitializerState {
  SE3d T_world_frame;                       // the first frame at the identity
  Eigen::Vector2d affine = Eigen::Vector2d::Zero();
  std::vector<double> inverse_distances;    // one per point of the first frame
};

struct InitializerLevelSolve {
  double rmse = 0.0;     // RMS residual over the valid patches' pixels; +∞ with none
  int num_valid = 0;     // patches valid at the result
  int num_points = 0;    // patches in the level's problem (valid at the start)
  int iterations = -1;   // the solver's; −1 where nothing was solved
};

struct InitializationResult {
  bool done = false;
  SE3d T_frame_first;                               // scale: mean inverse distance 1
  // One frame's motion at the end, T_frame_previous, for the tracker's first velocity (the
  // first frame can lie tens of frames back): the rotation of the last step; the translation
  // of the mean step over the frames tried, since before the snap the steps' translation is
  // held near zero (pre_snap_translation_penalty).
  SE3d T_frame_previous;
  Eigen::Vector2d frame_affine = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> pixels;              // level 0, first frame
  std::vector<double> inverse_distances;
  double parallax_px = 0.0;
  double parallax_deg = 0.0;  // RMS triangulation angle (min_parallax_deg)
  double rmse = 0.0;
  int snapped_at = -1;        // frames after the first when it snapped; −1 not yet
};

// The triangulation angle at which the initialiser snaps (InitializerOptions::snap_parallax_deg).
inline double snapParallaxDeg(const InitializerOptions& o) {
  return o.snap_parallax_deg < 0 ? o.min_parallax_deg : o.snap_parallax_deg;
}

class Initializer {
 public:
  Initializer(const Camera& camera, const Mask& mask, InitializerOptions options = {});
  ~Initializer();

  // The first frame (photometrically corrected) and its exposure.
  void setFirstFrame(std::shared_ptr<const ImagePyramid> pyramid, double exposure);
  bool hasFirstFrame() const;
  int numFramesTried() const;
  // Aligns a new frame to the first; done when the baseline suffices.
  InitializationResult addFrame(const ImagePyramid& frame, double exposure);
  // A human-readable account of the last attempt (why it is not done yet).
  const std::string& status() const;
  // Compute threads for the rotation search's candidate costs (task_pool.hpp; the result
  // does not depend on them). Not owned; null: the calling thread alone.
  void setTaskPool(TaskPool* pool);

  // The steps of addFrame, on a given state instead of the initialiser's own (which they
  // leave unchanged): the current state; one level's solve (before or after the snap);
  // and the rotation search's cost at each candidate pose (the points selected at
  // candidates[0]), the search taking the first of the least — with least_only, as the
  // search computes them: a candidate's sum is cut short (+∞) once it exceeds the least
  // cost seen so far, which never cuts the first of the least.
  InitializerState state() const;
  InitializerLevelSolve solveLevel(const ImagePyramid& frame, double exposure, int level,
                                   bool snapped, InitializerState* state);
  std::vector<double> rotationSearchCosts(const ImagePyramid& frame, double exposure, int level,
                                          bool snapped, const InitializerState& state,
                                          const std::vector<SE3d>& candidates,
                                          bool least_only = false);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnidso
