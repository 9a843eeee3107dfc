#pragma once
// Coarse-to-fine direct image alignment of a new frame to the newest keyframe (paper
// Sec. V-C "Initial Frame Tracking"; DSO Sec. 3.1): the window's active points, expressed in
// the newest keyframe (pixel + inverse distance), are aligned to the new frame over a
// 5-level pyramid, estimating the relative pose T_frame_ref and the frame's affine
// brightness [a, b] with the tracking residual (residuals/tracking_residual.hpp; one pixel
// per point, as DSO's tracker) in a small Ceres problem per level, or by the native solver
// (tracker_solver.hpp; CoarseTrackerOptions::native_solver).
//
// Coarser levels: the points falling into one coarse pixel are merged (mean inverse
// distance) — the coarse image averages them too.
// Hypotheses (DSO): constant velocity, double, half and zero motion, the reference pose
// itself, the last step reversed (`reversed_step_hypothesis`; not DSO's), then the
// constant-velocity guess turned by `rotation_hypothesis_rad` about each of
// the 26 directions (i, j, k) ∈ {−1, 0, 1}³ \ 0 (DSO's offsets: 0.04 rad per axis), and
// by `wide_rotation_hypothesis_rad` likewise when it is set;
// each is tried coarse to fine, and dropped after the coarsest level when its error exceeds
// `early_reject_factor` × the best coarsest-level error so far. Trying stops as soon as a
// hypothesis ends below `good_enough_factor` × the previous frame's error.
// When none ends below that (a frame no hypothesis tracks well enough), the hypotheses are
// tried once more on the reference dilated by one pixel per level (`dilated_retry`,
// reference_dilation.hpp), and the winner there, tracked once more on the plain reference,
// replaces the first result if it ends lower.
// The winner may be solved once more at the finest level alone (the second start below).
// Success: enough points stay valid and the final error is finite.
// Flow statistics for the keyframe decision (DSO): RMS pixel shift of the points under the
// translation alone (flow_t) and under the full motion (flow_rt), at level 0.
//
// The affine gauge. The residual (tracking_residual.hpp) compares I_j − b_j with
// s (I_ref − b_ref), s = t_j e^{a_j} / (t_ref e^{a_ref}): only the transfer (s, b_j − s b_ref)
// is seen by the data, but the affine prior below ties [a_j, b_j] themselves to the guess.
// With exposure times the window ties every b to 0 and that is the same. Without them the
// window's [a, b] drift: on the uncalibrated forward path H7, a to −1.9 and b to 60–120
// intensity units (each new keyframe's contrast a few percent low, b making up the mean).
// A frame's b_j then held at b_ref makes a gain change s a brightness change about b_ref
// instead of about black: a uniform error (1 − s) b_ref. `affine_in_reference_gauge` solves
// instead for b' = b_j − s b_ref (the reference's b taken as 0) and converts back, so that the
// prior ties the transfer's offset — about black, where a change of exposure or gain leaves it
// — and the result does not depend on the window's gauge. Off by default (with exposure times
// the window ties b to 0 and the two are the same); `omnidso run` turns it on for data without
// exposure times, with the gain's prior dropped (cli::applyPhotometricMode; docs/performance.md,
// "The tracker's affine gauge" and "Without exposure times: the gain free, the offset tied").

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/residuals/photometric_residual.hpp>
#include <vector>

namespace omnidso {

struct TrackingReferencePoint {
  Eigen::Vector2d pixel;    // level 0, in the reference keyframe
  double inverse_distance;  // 1/‖x‖ in the reference keyframe
};

struct CoarseTrackerOptions {
  int num_levels = 5;
  // Iterations per level, finest first; levels beyond the list take its last entry. Setting
  // `tracker.max_iterations` (a list: `--set tracker.max_iterations=6,8,10,12,15`).
  std::vector<int> max_iterations = {6, 8, 10, 12, 15};
  // Ceres's function_tolerance: a level stops once an iteration lowers its cost by less than
  // this fraction (DSO stops once its increment is small). 1e-3 against Ceres's 1e-6: the
  // same keyframe ATE on four rendered sequences, tracking 35–50 % faster
  // (docs/performance.md).
  double function_tolerance = 1e-3;
  double huber_threshold = 9.0;
  // The image gradient in the Jacobians: false, the bilinear interpolant's derivative; true,
  // central differences blended bilinearly (DSO's; core/interpolation.hpp). Off: on H12p and
  // own preset C the tracker's part alone was worse (docs/performance.md, "The image
  // gradient in the Jacobians").
  bool central_difference_gradients = false;
  // Each level's reference points dilated by one pixel (reference_dilation.hpp; DSO's coarse
  // tracker does the same): the diagonal neighbours on levels 0 and 1, the direct ones from
  // level 2 on. Setting `tracker.dilate_reference`.
  bool dilate_reference = false;
  // The retry on the dilated reference: when no hypothesis ends below `good_enough_factor` ×
  // the previous frame's error, the hypotheses are tried again on the reference dilated as
  // above (once more, if `dilate_reference` is set) with `retry_max_iterations` per level, and
  // its winner, tracked once more on the plain reference (with `max_iterations`), replaces the
  // first result where it ends lower there.
  // Why: the dilated reference has more terms per level, and its coarse levels' valleys reach
  // further; on H12p at 10 Hz a turn that sped up from 5° to 15° per frame left the
  // constant-velocity guess 10° short, every hypothesis ended in another minimum (error 3.4×
  // the previous frame's, 8.5° off), and the keyframe made there set the map's scale 30 % high
  // for the rest of the run; the original DSO, whose reference is dilated, tracked it. Dilated
  // on every frame the reference costs accuracy where the plain one tracks well (a dilated
  // point takes its neighbours' inverse distance across depth edges: H12p 0.098 → 0.126 %, own
  // preset C 5×) and triples the tracking time; as a retry it runs on the frames that need it
  // (H12p at 20 Hz and the development set: once in a run, or never) and the result is judged
  // on the plain reference. H12p10 0.425 → 0.107 %, with the reversed step and the retry's
  // budget below D2's crop at 10 Hz 4.6 → 0.34 % (docs/performance.md, "The tracker's
  // reference dilated"). Setting `tracker.dilated_retry`.
  bool dilated_retry = true;
  // The retry's iterations per level, finest first (DSO's budget: its tracker runs them on
  // every frame). On every frame here they cost H12p (0.098 → 0.140 %) and the development
  // set's crops; on the retry's frames alone they track D2's crop at 10 Hz through a
  // stop-and-go turn (9.7°, 2°, 9.3° per frame) that the default budget ended 8° off (same
  // section). Setting `tracker.retry_max_iterations` (a list, as `max_iterations`).
  std::vector<int> retry_max_iterations = {10, 20, 50, 50, 50};
  double early_reject_factor = 1.5;
  double good_enough_factor = 1.5;  // DSO's re-track threshold
  double min_valid_fraction = 0.3;
  double rotation_hypothesis_rad = 0.04;
  // The last step reversed — the previous frame's pose, velocity⁻¹ · T_last_ref = T_prev_ref —
  // tried after DSO's five and before the turns. Why: a hand-held camera shakes, and a shake
  // reverses its turn from one frame to the next; then the constant-velocity guess lies two
  // steps from the truth and zero motion one, while the previous frame's pose lies only the
  // difference of the two steps away. On the development set's D2 at 10 Hz through the 90°
  // crop the pitch went −3.1° then +5.7°: the guess 8.8° off, zero motion 5.7° off, both
  // beyond the coarse levels' valley about that axis (2–4°, measured from the truth turned),
  // every hypothesis ended at 4× the truth's error, and the keyframe made there set the map's
  // scale 4.6× off (docs/performance.md, "The last step reversed"). Setting
  // `tracker.reversed_step_hypothesis`.
  bool reversed_step_hypothesis = true;
  // A second ring of the 26 turns, at this angle, tried after the first (0: none). On a 90°
  // view at 10 Hz (H12p10, turns of up to 19° per frame) one frame tracked wrong in a fast
  // turn set the map's scale for the rest of the run; with 0.08 the six-seed median went
  // 0.425 → 0.102 %, near even elsewhere, hence off (docs/performance.md, "H12p at 10 Hz").
  double wide_rotation_hypothesis_rad = 0.0;
  // The second start at the finest level. When coarse to fine lowered the finest-level error
  // by less than `second_start_gain` (10 %) of the error at the winning hypothesis itself, the
  // hypothesis already lay near a finest-level minimum, and the finest level alone is solved
  // once more from it. Where the two results are different minima — more than
  // `second_start_min_shift_px` apart (RMS over the level-0 points) — the lower finest-level
  // error wins; closer, they are one minimum reached by two paths and coarse to fine is kept.
  // Why: the coarse levels widen the basin but see motion along the optical axis poorly (its
  // radial flow is a fraction of a coarse pixel over most of the image), so a coarse level can
  // walk along the axis on a flat cost and hand the finer levels a start outside the true
  // minimum's basin, where they stop in another. Found on the uncalibrated forward path H7 at
  // its dimmest frames: from the constant-velocity guess the coarse levels doubled the step
  // along the axis (finest error 4.90) where the finest level alone stayed with the guess
  // (4.71), and the keyframe made there broke the scale (docs/performance.md, "The tracker's
  // coarse levels along the optical axis"). The gate keeps the cost off frames whose guess
  // was far: hand-held, coarse to fine lowers the error by half or more and the second start
  // runs on under 1 % of the frames; on H7 on 75 %. Every second start adopted on H7 followed
  // a gain under 4 %. 1 px: the finest level's basin is about a pixel wide (bilinear samples,
  // one-pixel gradients). Settings `tracker.finest_level_second_start`,
  // `tracker.second_start_gain`, `tracker.second_start_min_shift_px`.
  bool finest_level_second_start = true;
  double second_start_gain = 0.1;
  double second_start_min_shift_px = 1.0;
  int num_threads = 1;
  // Solve for the frame's offset in the reference's gauge (above). Setting
  // `tracker.affine_in_reference_gauge`.
  bool affine_in_reference_gauge = false;
  // Gaussian priors pulling the frame's affine [a, b] (b' with `affine_in_reference_gauge`)
  // towards the guess. With calibrated exposure times and response (DSO's photometric mode)
  // the brightness model needs no correction, so DSO ties them almost rigidly: a free (a, b)
  // otherwise absorbs the contrast loss of bilinear interpolation at high-gradient pixels (a
  // few percent, a < 0). Weights in energy per unit². The guess is the previous frame's.
  // Without exposure times the gain is what changes, and `omnidso run` drops the prior on a
  // (as DSO's tracker has none) and keeps the one on the offset, about black
  // (cli::applyPhotometricMode).
  double affine_prior_weight_a = 1e8;
  double affine_prior_weight_b = 1e6;
  // Solve each level with the native Levenberg–Marquardt solver (tracker_solver.hpp) instead
  // of a ceres::Problem: the same problem and the same Ceres semantics (trust region, Jacobi
  // scaling, tolerances), the same result up to rounding, without Ceres's per-frame problem
  // building and per-residual-block plumbing. Setting `tracker.native_solver`. On by default:
  // on D1–D4 (seed 0) tracking 4–5× faster, the full image's keyframe ATE the same to the
  // third digit; the crop's runs move within their seed spread (docs/performance.md, "The
  // native tracker solver"). false keeps the ceres::Problem path, the test oracle.
  bool native_solver = true;
};

// One level's solve (CoarseTracker::solveLevel): the error of the result — RMS of the
// Huber-clamped residuals still valid — and the solver's iterations (Ceres's
// summary.iterations.size() − 1; −1 when fewer than 8 residuals were valid and nothing was
// solved).
struct TrackingLevelSolve {
  double rmse = std::numeric_limits<double>::infinity();
  double valid_fraction = 0.0;
  int iterations = -1;
};

struct TrackingResult {
  bool ok = false;
  SE3d T_frame_ref;
  Eigen::Vector2d affine = Eigen::Vector2d::Zero();  // [a, b] of the new frame
  std::vector<double> level_rmse;                     // finest first
  double rmse = 0.0;                                  // level 0
  double valid_fraction = 0.0;
  double flow_t = 0.0;   // RMS shift, translation only (px)
  double flow_rt = 0.0;  // RMS shift, full motion (px)
  int hypotheses_tried = 0;  // on both references when the retry ran
  bool dilated_retry = false;  // the retry on the dilated reference ran
};

class CoarseTracker {
 public:
  CoarseTracker(const Camera& camera, CoarseTrackerOptions options = {});
  ~CoarseTracker();

  // The reference: the newest keyframe's pyramid, exposure, affine and points.
  void setReference(std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                    const Eigen::Vector2d& affine, const std::vector<TrackingReferencePoint>& points);
  bool hasReference() const;
  int numReferencePoints(int level = 0) const;

  // hypotheses: T_frame_ref candidates, most likely first. affine_guess: [a, b] to start from.
  TrackingResult track(const ImagePyramid& frame, double exposure,
                       const std::vector<SE3d>& hypotheses, const Eigen::Vector2d& affine_guess,
                       double previous_rmse) const;

  // One level's solve from T_frame_ref and affine, which move in place (what track() does
  // per level and hypothesis; for tests comparing the solvers).
  TrackingLevelSolve solveLevel(const ImagePyramid& frame, double exposure, int level,
                                SE3d* T_frame_ref, Eigen::Vector2d* affine) const;

  // DSO's hypothesis list around a constant-velocity guess (velocity · T_last_ref, velocity =
  // T_last_prev), with the reversed step after DSO's five when it is set.
  std::vector<SE3d> makeHypotheses(const SE3d& T_last_ref, const SE3d& velocity) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace omnidso
