#pragma once
// The Odometry facade: frames in, poses, points and timings out (paper Fig. 3; DSO's
// pipeline). One frame:
//   1. not initialised: the Initializer aligns it to the first frame; once the baseline
//      suffices, both become keyframes of the window with the initial points (the first
//      segment's start is raced against a rival's: InitializationRaceOptions);
//   2. CoarseTracker: align to the newest keyframe's points, coarse to fine → pose, affine;
//      tracking failure ends the segment: say so, re-initialise from the next frames;
//   3. every window keyframe's immature points are searched along their epipolar curves;
//   4. keyframe decision: no → done;
//   5. yes: SlidingWindow::addKeyframe → activate converged immature points → optimise →
//      remove outliers → marginalise (policy of Sec. V-C) → new immature points → new
//      tracking reference.
// Deterministic: single-threaded, and the only randomness (pixel selection directions) is
// seeded from OdometryOptions::seed, so the same input gives the same trajectory bit for bit.

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/camera_encoding.hpp>
#include <omnidso/frontend/activation_density.hpp>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/frontend/keyframe_decision.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/frontend/reference_depth_consistency.hpp>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace omnidso {

// The initialisation race (docs/architecture.md, "The initialisation race"). Through a narrow
// view the first pair can settle in a wrong basin of the rotation–translation ambiguity, and
// no snap angle tells which frame does (initializer.hpp, snap_parallax_deg: on a fast turn the
// default's snap at 5° failed where one at 2° held; on D2's crop the reverse). The first
// segment is therefore started twice on the same frames: as configured, and as a rival that
// snaps at `rival_snap_parallax_deg`. Once each window has held `keyframes` keyframes (or lost
// tracking before, or restarted its initialisation past the other's first frame, which count
// as an infinite cost: decideRace), the rival replaces the configured start
// only if its window's cost RMS, √(2 E / (8 n)) over the n residual patches at the optimum, is
// below `switch_gain` × the other's. On the same frames a wrong basin's cost was 1.4–3.2× a
// right one's, two right ones within 0.87–1.11× of each other (docs/performance.md, "The
// initial pair's basin through a narrow view"); but right rivals also lost at 0.83–0.94× (a
// start inside a fast turn under blur, car paths K1 and K12: docs/performance.md, "K12, a car
// path the original DSO follows, and the race's gain"), and where both are right either
// serves: 1, the lower cost wins. Except where the two starts agree: when the frame the race
// is decided on has the same pose relative to the start frame in both — rotations and
// directions of travel within `same_start_deg` — they found the same solution, their costs
// differ by the images their keyframes hold, and the configured start, triangulated at the
// larger angle, stays. On a narrow MAV render (E2) the rival was 0.96–0.97× as costly at
// 0.06° and 0.2° from the configured start, and 4–5× less accurate. Two starts of one solution
// were 0–0.3° apart in rotation and 0–1.4° in direction on the fisheye and MAV renders, up to
// 1.1° and 3.6° on car strips; the rivals that rescued a run 1.4–21° and 3.4–62°. The bound
// lies below both: a pair it misses is decided by the costs, as before (docs/performance.md,
// "Two starts that agree").
// At its snap the rival adopts the lowest-error start (`rival_snap_translation_start_gain`, the
// initialiser's snap_translation_start_gain, 1: the lowest): the configured start's 0.95× rule
// keeps the pre-snap path's solution unless another is clearly better, and in a fast turn
// under motion blur the right basin's two-frame error was only 0.98–0.99× the wrong one's
// (docs/performance.md, "A start inside a fast turn"). Between the two starts the race, not the
// two-frame error, decides.
// Until then every frame is processed twice (the frames' timings count one side, the wall
// time both) and the accessors show the configured start; a rival that snaps on the
// configured start's frame and adopts the same start there (the same initial pose, bit for
// bit) would repeat it and is dropped then. Later segments (after a tracking loss) and the
// real-time mode do not race.
struct InitializationRaceOptions {
  double rival_snap_parallax_deg = 2.0;  // ≤ 0, or not below the configured snap angle: no race
  int keyframes = 3;                     // 2 … the window's size
  double switch_gain = 1.0;
  double same_start_deg = 1.0;           // ≤ 0: the costs alone decide
  int max_frames = 200;                  // undecided after this many frames: the rival is dropped
  double rival_snap_translation_start_gain = 1.0;  // > 0; the configured start's: 0.95
};

struct OdometryOptions {
  // Active points aimed at (DSO's N_p): the density of activation's grid, one point per cell
  // of area/num_points in the newest keyframe (activation_grid.hpp), not a cap on the window.
  int num_points = 2000;
  int num_candidates = 2000;     // immature points selected per keyframe
  // Levels of every image pyramid (tracking, initialisation); 0: pyramidLevelsForImage of
  // the camera's image size (core/pyramid.hpp), which also caps tracker.num_levels.
  int pyramid_levels = 0;
  // Pixels this close to a pixel without content (outside the camera's domain or the image
  // mask, e.g. the black surround of a fisheye's image circle) are not selected; −1:
  // defaultContentMarginPx(pattern_spread), below.
  int content_margin_px = -1;
  // Target samples (tracking, initialisation, window, epipolar search, activation) whose
  // bilinear footprint touches a pixel without content on their pyramid level are invalid,
  // as samples outside the image are (core/content_mask.hpp, contentPyramid). false: only
  // the image rectangle and the model's domain bound them (an ablation).
  bool reject_targets_outside_content = true;
  // How the camera encodes the frames' corrected intensities (camera_encoding.hpp): the
  // response's slope and the vignette on the odometry's grid, from the dataset's photometric
  // calibration (null: linear). The odometry hands it to pixel selection
  // (PixelSelectorOptions::encoding, read with `selection.camera_encoding`). With
  // `noise_in_encoding` every frame's pyramid offers s = ∂I/∂E, and the residuals of the
  // initialiser, the window and activation weigh each pattern pixel by it
  // (photometric_residual.hpp, makeHostPatch): right when the camera's
  // noise is uniform in its encoding rather than in E. The tracker's are not weighed
  // (coarse_tracker.cc says why). Off by default: it depends on where the camera adds its
  // noise (docs/performance.md, "Residuals weighed in the camera's encoding" and "The noise
  // measured; …"). Without a photometric calibration it changes nothing.
  // The residuals are then in the encoding's units, and so is the initialiser's photometric
  // error that `initializer.max_rmse` bounds: where the noise comes before the response that
  // error is larger, and on one such render the initialiser never accepted (17.4 against 15).
  std::shared_ptr<const CameraEncoding> camera_encoding;
  bool noise_in_encoding = false;
  // The residual pattern's step in pixels, for every pattern user (window, initialiser,
  // activation, epipolar search; residual_pattern.hpp, spreadOffset). 1 is DSO's pattern. On
  // an image magnified k× from its source, k puts the pattern on the source's pixels
  // (docs/performance.md, "The narrow view without resampling"); `omnidso run` sets it so for
  // pinhole crops (cli::applyCropPatternSpread). At most 8.
  int pattern_spread = 1;
  std::uint64_t seed = 0;
  WindowOptions window;
  CoarseTrackerOptions tracker;
  // With neighbours > 0 the tracking reference keeps only the points whose inverse distance
  // agrees with their image neighbours' (reference_depth_consistency.hpp; off by default,
  // `omnidso run` turns it on for narrow views: cli::applyNarrowViewTracking).
  ReferenceDepthConsistencyOptions reference_depths;
  EpipolarSearchOptions epipolar;        // max_search_px 0 → 0.027 (w + h)
  KeyframeDecisionOptions keyframe_decision;
  KeyframeMarginalizationOptions marginalization;
  InitializerOptions initializer;
  double max_activation_interval_px = 8.0;  // immature point converged enough to activate
  double min_activation_quality = 3.0;
  // The activation grid's cell adapted to the window's point count (activation_density.hpp).
  ActivationDensityOptions activation_density;
  // Converged candidates are optimised against every window keyframe before activation;
  // unobserved ones wait, inconsistent ones are dropped (new_point_refinement.hpp).
  NewPointRefinementOptions activation;
  int max_keyframe_interval_frames = 0;      // > 0: force a keyframe after this many frames
  // Real-time mode: mapping (epipolar search, keyframes, window, marginalisation) in its own
  // thread while addFrame tracks the next frames; a lagging mapper skips the search in
  // non-keyframes. Not repeatable bit for bit (it depends on thread timing); off by default.
  bool realtime = false;
  // Threads for the steps that split into independent work (epipolar search, the window's
  // evaluation and the marginalisation's linearisation, candidate refinement, the new
  // candidates beside the marginalisation, the initialiser's rotation search), the caller
  // included; 0: the hardware threads (at most 8). Each step is split so that every sum is
  // formed by one task in a fixed order: the trajectory is the same bit for bit for any count
  // (core/task_pool.hpp).
  int compute_threads = 1;
  InitializationRaceOptions race;
};

struct FrameTiming {
  double tracking_ms = 0.0;  // direct image alignment and the keyframe decision
  double search_ms = 0.0;    // epipolar-curve search of the immature points (DSO does it in
                             // its mapping thread; here it runs after tracking)
  // Keyframes only: everything done for the keyframe (mapping_ms), and its stages in order:
  // entering the window and activating candidates (activation_ms), the window optimisation,
  // outlier removal (outliers_ms), the marginalisation together with the new keyframe's
  // candidates (marginalization_ms: with compute threads the two run side by side), and the
  // tracking reference (selection_ms). The stages sum to mapping_ms up to the stopwatches'
  // own cost.
  double mapping_ms = 0.0;
  double activation_ms = 0.0;
  double window_ms = 0.0;
  double outliers_ms = 0.0;
  double marginalization_ms = 0.0;
  double selection_ms = 0.0;
};

struct FrameRecord {
  int index = 0;
  double timestamp = 0.0;
  bool tracked = false;      // has a pose (initialised and tracked)
  bool is_keyframe = false;
  int segment = 0;           // increases after every re-initialisation
  int reference_keyframe = -1;
  SE3d T_frame_ref;          // pose relative to its reference keyframe
  FrameTiming timing;
};

struct KeyframeRecord {
  int id = 0;  // = frame index
  double timestamp = 0.0;
  int segment = 0;
  SE3d T_world_cam;  // latest estimate (final once marginalised)
};

// Stored for the whole run (hundreds of thousands on long sequences): single precision
// keeps the map at 20 bytes a point — a micrometre at 10 m.
struct OdometryPoint {
  Eigen::Vector3f position_world;
  float intensity = 0.f;
  int segment = 0;
};

// What content_margin_px = −1 stands for: the margin hostPatchFits (photometric_residual.hpp)
// keeps from the image's border, hostPatchReachPx — DSO's pattern on steps of
// `pattern_spread` pixels and the central differences of the host's gradients, pattern
// radius × spread + 1 — kept from the content's edge as well, so that no level-0 host sample
// touches the black surround. The coarse levels' host samples near the edge do average some
// of it in; their targets are checked against each level's content, so the fixed edge is
// never compared with itself.
// The margin was 2^levels + 3 (19 px on a 480-pixel image), the coarsest level's reach: on a
// 120° image circle of 106 px radius it took a fifth of the radius from selection, and 7 runs
// in 40 lost their scale in a fast turn, none with this margin (docs/performance.md, "A 120°
// image circle in a fast turn").
int defaultContentMarginPx(int pattern_spread);

// The rival's options (InitializationRaceOptions): the configured ones with the rival's snap
// angle and snap start gain.
OdometryOptions raceRivalOptions(const OdometryOptions& options);

// One side of the initialisation race, as its decision sees it.
struct RaceSide {
  RaceSide(int start, double side_cost, bool side_lost,
           std::optional<SE3d> pose = std::nullopt)
      : start_frame(start), cost(side_cost), lost(side_lost), T_start_current(std::move(pose)) {}
  // The first frame of the side's first segment: the one it initialised from, or, not
  // initialised yet, its initialiser's first frame — which a restart (initializer.max_frames)
  // moves on.
  int start_frame = -1;
  double cost = std::numeric_limits<double>::quiet_NaN();  // at race.keyframes keyframes
  bool lost = false;  // tracking lost (before it had its cost: +∞)
  // The pose of the frame the race is decided on relative to the start frame, T_start_frame;
  // unset where the side has not tracked that frame.
  std::optional<SE3d> T_start_current;
};
enum class RaceOutcome { kUndecided, kKeepConfigured, kTakeRival };
struct RaceDecision {
  RaceOutcome outcome = RaceOutcome::kUndecided;
  int common_start = -1;  // the earlier of the two sides' start frames
  double configured_cost = std::numeric_limits<double>::quiet_NaN();  // as compared (+∞: lost)
  double rival_cost = std::numeric_limits<double>::quiet_NaN();
  // Between the two sides' T_start_current (NaN where either is unset, or a translation is
  // zero): the angle of the relative rotation, and the angle between the directions of travel.
  double rotation_apart_deg = std::numeric_limits<double>::quiet_NaN();
  double direction_apart_deg = std::numeric_limits<double>::quiet_NaN();
  bool same_start = false;  // both within same_start_deg: the configured start kept
};
// The race compares two starts from the same frames. A side that lost tracking before its
// window held race.keyframes keyframes, or that could not initialise from the frames the other
// started from (its start moved on by a restart), costs +∞; the rival is taken only when its
// cost is below switch_gain × the configured one's. Undecided while a cost is unknown. (A rival
// that restarted at frame 60 of a fast car-like strip and initialised at frame 125 had been
// taken at its lower cost, dropping 120 tracked frames: docs/performance.md, "The race
// between starts from different frames".) A rival that would be taken is not where both
// sides started from the same frame and their T_start_current lie within same_start_deg of
// each other in rotation and in the direction of travel (InitializationRaceOptions); ≤ 0, or a
// pose unset: the costs alone.
RaceDecision decideRace(const RaceSide& configured, const RaceSide& rival, double switch_gain,
                        double same_start_deg = 0.0);

class Odometry {
 public:
  // camera: distortion-free model (pinhole, ucm, eucm, ds, kb4, fov) of the images passed in.
  // image_mask (optional, camera-sized): 0 marks pixels without image content (outside the
  // source image after rectification, or outside a fisheye's image circle:
  // detectContentMask); combined with the camera's own validity mask, then eroded by
  // OdometryOptions::content_margin_px.
  Odometry(const Camera& camera, OdometryOptions options = {}, const Mask& image_mask = Mask());
  ~Odometry();

  // image: photometrically corrected intensities (0..255 scale), camera-sized.
  // exposure: t, any unit consistent over the sequence (1 when unknown).
  // In the real-time mode the record's keyframe flag and timings are final only once the
  // mapping thread has caught up (finish(), or any accessor below).
  const FrameRecord& addFrame(const ImageF& image, double timestamp, double exposure);

  // In the real-time mode the accessors below first wait for the mapping thread.
  const std::deque<FrameRecord>& frames() const;
  // Real-time mode: waits until every frame added so far has been mapped (no-op otherwise).
  void finish();
  // T_world_cam of a frame through the latest estimate of its reference keyframe.
  SE3d framePose(const FrameRecord& frame) const;
  std::vector<KeyframeRecord> keyframes() const;
  std::vector<OdometryPoint> points() const;  // marginalised and active points
  // The same points one by one, without copying the map (writers of long runs).
  void forEachPoint(const std::function<void(const OdometryPoint&)>& visit) const;
  size_t numPoints() const;
  // Long runs: hand every point to `sink` when it leaves the window (marginalised with its
  // host, or kept at a tracking loss) instead of storing it, so that memory stays bounded by
  // the window rather than growing with the map (20 bytes a point: 15 MB for 12 000 frames).
  // Points handed over are no longer returned by points(), forEachPoint() or numPoints(),
  // which then hold the active points only. Set it before the first frame; in the real-time
  // mode it is called from the mapping thread.
  void setRetiredPointSink(std::function<void(const OdometryPoint&)> sink);
  bool initialized() const;
  // The intrinsics as currently estimated (the calibration's while nothing is optimised).
  Eigen::VectorXd intrinsics() const;
  int numSegments() const;
  // Events a user should see: initialisation, tracking loss, re-initialisation.
  const std::vector<std::string>& log() const;
  // Why the current segment is not initialised yet (empty once it is).
  std::string initializationStatus() const;

 private:
  struct Impl;
  // The race's end (InitializationRaceOptions): the rival dropped, or made the odometry.
  void settleRace();
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<Impl> rival_;  // while the initialisation race lasts
};

}  // namespace omnidso
