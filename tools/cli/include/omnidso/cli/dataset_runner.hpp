#pragma once
// The odometry over a dataset, as `omnidso run` does it and as the end-to-end tests do it:
// every frame is read, corrected photometrically (pcalib.txt, vignette.png — or, without it, a
// vignette estimated from the frames: dataset_vignette.hpp), rectified when
// the calibration has distortion or a pinhole crop is asked for (`pinhole-crop:FOV_DEG`, the
// paper's "DSO with the pinhole model" baseline), and fed to omnidso::Odometry.

#include <functional>
#include <memory>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/vignette_estimation.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <optional>
#include <string>

namespace omnidso::cli {

struct DatasetRunOptions {
  // native | native-fov:FOV_DEG (the native model, pixels beyond FOV/2 from the optical axis
  // masked: the field-of-view ablation without resampling) | pinhole-crop:FOV_DEG
  std::string camera_model = "native";
  std::string calib;                    // overrides the dataset's calibration file
  size_t max_frames = 0;                // 0: all
  // Mask the black surround of a fisheye's image circle, detected in the first frames
  // (core/content_mask.hpp).
  bool detect_content = true;
  // Real-time mode only: frames are fed at their timestamps' pace times this factor, as a
  // camera would deliver them (0: as fast as they can be read).
  double playback_speed = 1.0;
  // Read, decode, photometrically correct and rectify frame i+1 on a second thread while the
  // odometry processes frame i. The odometry sees the same images in the same order, so the
  // trajectory is the same bit for bit; only the wall time changes (reading and resampling
  // were ≈ 10 % of a run). false reads each frame when it is due, on the calling thread.
  bool prefetch = true;
  // Without vignette.png, estimate the vignette from the frames (dataset_vignette.hpp) and
  // divide it out; false takes the images as unvignetted.
  bool estimate_vignette = true;
  OdometryOptions odometry;
  std::function<void(size_t done, size_t total, const Odometry&)> progress;
  // Optional: receives every point that leaves the window (Odometry::setRetiredPointSink).
  std::function<void(const OdometryPoint&)> retired_point_sink;
};

struct DatasetRun {
  Camera source;  // the dataset's calibration
  Camera camera;  // what the odometry runs on
  std::unique_ptr<Odometry> odometry;
  std::optional<VignetteEstimate> vignette_estimate;  // set when one was attempted
  size_t frames_processed = 0;
  double wall_s = 0.0;
};

// "native" and "native-fov:FOV" → nullopt, "pinhole-crop:FOV" → FOV; throws omnidso::Error
// otherwise.
std::optional<double> parsePinholeCrop(const std::string& camera_model);
// "native-fov:FOV" → FOV, other names → nullopt; a malformed FOV throws omnidso::Error.
std::optional<double> parseNativeFov(const std::string& camera_model);

DatasetRun runOdometryOnDataset(const DatasetIndex& index, const DatasetRunOptions& options);

// True when every frame's exposure time is given (times.txt's third column in the TUM layout;
// the ASL layout records none).
bool exposureTimesKnown(const DatasetIndex& index);

// The photometric model, chosen by the data. With exposure times the brightness from keyframe
// to keyframe is t_j/t_i, so the window ties every keyframe's affine [a, b] to 0
// (WindowOptions::affine_prior_weight_*; DSO's calibrated mode). Without them the camera's
// auto-exposure changes each frame's gain, which only the affine model can explain: a tie of a
// to 0 asserts that every keyframe had the same exposure (a 2.5× change over the development
// set's MAV path). A change of exposure or gain scales the values about black — linear ones,
// and gamma-encoded ones too, (k E)^γ = k^γ E^γ — and leaves the offset (the black level)
// alone. So the gain goes free and the offset stays tied to 0: the window drops its tie on a,
// the tracker its prior on a (DSO's tracker has none) and ties its offset about black, not
// about the reference's offset (CoarseTrackerOptions::affine_in_reference_gauge). DSO's
// uncalibrated mode frees b as well; a free window b drifted to 60–120 on the uncalibrated
// held-out path H7 and failed it (docs/performance.md, "Without exposure times: the gain free,
// the offset tied"). The initialiser's prior stays (it ties a frame to the segment's first).
// Call it before the user's settings so that they can override it. Returns a note for the
// user when it changed the options, else "".
std::string applyPhotometricMode(const DatasetIndex& index, OdometryOptions* options);

// For `pinhole-crop:FOV`, the residual pattern on the source's pixels: pattern_spread = the
// crop's magnification of the source at its centre, rounded (cameras/rectification.hpp,
// magnificationAtPrincipalPoint; 1 … 8). On a crop magnified 2.6× DSO's pattern covers less
// than two source pixels, and D2's crop lost its scale in every seed (docs/performance.md,
// "The narrow view without resampling"). Returns a note saying so, or "" for other models,
// whose spread stays 1. Call before the user's settings, which override it.
std::string applyCropPatternSpread(const DatasetIndex& index, const DatasetRunOptions& run,
                                   OdometryOptions* options);

// The view at and beyond which the intrinsics go free (applyIntrinsicsPrior): a hemisphere.
constexpr double kSelfCalibratingViewDeg = 180.0;

// The widest angle the odometry sees, in degrees: twice the largest angle from the optical
// axis over the calibration's valid pixels — within the image content detected in the first
// frames (the black surround of an image circle excluded) and within `native-fov:FOV` — and,
// for `pinhole-crop:FOV`, the crop's own.
double viewWidthDeg(const DatasetIndex& index, const DatasetRunOptions& run);

// The calibration prior, chosen by the view. The window optimises the intrinsics jointly
// (the paper), held near the calibration by DSO's prior (WindowOptions::
// intrinsics_prior_weight). A view of a hemisphere or more observes them: a shift of the
// principal point is no longer a turn of every camera, nor a change of focal length a motion
// along the axis, once rays across the whole hemisphere are in the image. There the prior goes
// (weight 0) and the intrinsics correct the calibration's errors: on the development set's
// 190° images, started 0.5 % / 0.7 px off, they end within 0.2 % and 0.3 px of the truth and
// the keyframe ATE at its calibrated level (0.087 → 0.021 %; held, D1 drifted by +12 %); with
// an exact calibration the ATE stays as it was on the development set's mean (0.019 %) and
// doubles on the project's own renders (0.004 → 0.010 %). On narrower views the free
// intrinsics wander — a 90° pinhole's focal length by −15 % on forward motion, a crop's by
// 0.7 % — so they keep the prior; a crop's intrinsics are exact by construction anyway
// (docs/performance.md, "The calibration's errors: free intrinsics on a hemisphere").
// Call before the user's settings, which override it. Returns a note, or "" when unchanged.
std::string applyIntrinsicsPrior(const DatasetIndex& index, const DatasetRunOptions& run,
                                 OdometryOptions* options);
// The same for a width already measured (viewWidthDeg).
std::string applyIntrinsicsPrior(double view_width_deg, OdometryOptions* options);

// Below this the view is narrow (applyViewProfile): a 90° pinhole reaches 109.5° at its
// corners (EuRoC's camera 107.7°), where the narrow view's window gained; at 120°
// (`native-fov:120`, a fisheye masked to a 120° cone, and a 120° lens's image circle, which
// reads 119.98° over its content) it lost, at 135.6° (`pinhole-crop:120`'s corners) it was
// even (docs/performance.md, "A narrow view's window by the view's width"). The threshold lies
// between the evidence, not on either side of it.
constexpr double kNarrowViewBelowDeg = 115.0;

// The window's solve, chosen by the view and the photometric data. A narrow view with every
// frame's exposure time solves its window on DSO's image gradient (central differences blended
// bilinearly, `window.central_difference_gradients`) with three iterations per keyframe
// (`window.max_iterations`), as DSO, which is made for such views, does. Measured side by side
// (docs/performance.md, "The narrow view's window again"; medians of seeds): a hand-held 90°
// pinhole render 0.098 → 0.040 % (scale drift −8.4 → −1.1 %), the same at 10 Hz 0.091 → 0.042 %
// — from 2.5–4× the original DSO's error to 1.1–1.8× —, the development set's 90° crops 0.077 →
// 0.068 %, the own presets' 0.180 → 0.140 %; forward motion through a 90° pinhole loses (0.116 →
// 0.183 %, still 3× ahead of the original DSO; at 10 Hz 0.042 → 0.048 %), and so do two held-out
// MAV paths made afterwards (15–18 %, 1.1–1.3× → 1.3–1.5× DSO's): a trade by motion, kept for the
// worst ratio to DSO over every narrow set (3.9× → 1.6×). Without exposure times
// the pair loses (the development set's crops 0.067 → 0.077 %, D3 0.100 → 0.135 % in every seed,
// where the original DSO reads 0.06 %; three iterations alone 0.146 %): there, and on wider
// views (the full fisheye image loses with it: D4, own presets A and C; a 120° image circle
// too), the window keeps the interpolant's own gradient and two iterations. Mapping costs 40–50 % more per keyframe
// where it applies. Call before the user's settings, which override it. Returns a note when it
// changed the options, else "".
std::string applyViewProfile(double view_width_deg, bool exposure_times_known,
                             OdometryOptions* options);

// The tracking reference's depth check chosen by the view (reference_depth_consistency.hpp):
// on a narrow view the tracker aligns only the reference points whose inverse distance agrees
// with their 8 nearest neighbours' (`reference_depths.neighbours`). A narrow view tells a
// sideways step from a turn only by parallax, so a wrong inverse distance turns part of the
// step into rotation; in a fast turn, where nearly every frame is a keyframe and the newest
// points have had the least baseline, that compounds into a scale collapse. Measured side by
// side (docs/performance.md, "A narrow view's tracking reference checked against its
// neighbours"): a 448-pixel fisheye's 90° crop turning 7–9° per frame at 15 Hz fell to a
// quarter of its scale (5.4 / 6.5 % of the path; the original DSO on the same crop 3.6–3.9 %)
// and holds it with the check (0.43 / 0.27 %). It is a trade: it takes the worst narrow runs
// down (two hand-held pinhole renders 0.31 → 0.08 % and 0.40 → 0.06 %, a car path 0.22 →
// 0.12 %) and costs the typical ones a little — the development set's crops most (mean of medians
// 0.078 → 0.098 %); 99 runs of the other narrow sets 0.86× in the geometric mean. With or
// without exposure times. A wide view keeps every point: it tells the two apart by the flow's
// direction, and there the check moved runs only within their seeds' spread. Call before the
// user's settings, which override it. Returns a note when it changed the options, else "".
std::string applyNarrowViewTracking(double view_width_deg, OdometryOptions* options);

}  // namespace omnidso::cli
