#pragma once
// What `omnidso run` writes into its output directory:
//   frames.txt, keyframes.txt  TUM format `t tx ty tz qx qy qz qw`, T_world_cam, dataset
//                              timestamps (frames: every tracked frame, through the final
//                              estimate of its reference keyframe)
//   points.ply                 ASCII PLY: x y z intensity segment (marginalised + active)
//   timing.csv                 frame,timestamp,tracked,keyframe,segment,tracking_ms,
//                              search_ms,mapping_ms,window_ms,marginalization_ms,
//                              activation_ms,outliers_ms,selection_ms (FrameTiming)
//   summary.json               settings, counts, timing statistics, segments and events,
//                              and — with ground truth — ATE after Sim(3) alignment per segment
// Trajectory segments (after a tracking loss) have separate gauges; each is evaluated on its
// own, and the headline ATE is that of the segment with the most keyframes.

#include <nlohmann/json.hpp>
#include <omnidso/cli/ply_point_writer.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/trajectory.hpp>
#include <optional>
#include <omnidso/frontend/odometry.hpp>
#include <ostream>
#include <string>

namespace omnidso::cli {

struct RunDescription {
  std::string dataset;
  std::string camera_model_option;
  std::string source_camera;
  std::string odometry_camera;
  int keyframes = 7;
  int points = 2000;
  bool optimize_intrinsics = true;
  std::uint64_t seed = 0;
  int threads = 1;
  int compute_threads = 1;  // as used (OdometryOptions::compute_threads, 0 resolved)
  std::string residuals;
  size_t frames_processed = 0;
  double wall_s = 0.0;
  nlohmann::json settings = nlohmann::json::object();  // every odometry setting (odometry_settings.hpp)
  nlohmann::json vignette_estimate = nullptr;  // dataset_vignette.hpp; null when none was tried
  // The view's width (dataset_runner.hpp, viewWidthDeg), whether it is narrow, and whether
  // the narrow view's window (applyViewProfile) and tracking reference
  // (applyNarrowViewTracking) were applied; null when not measured.
  nlohmann::json view = nullptr;
};

// ground_truth: the camera poses (synth::cameraGroundTruth), read by the caller before the
// run so that a bad file stops it early; nullopt when the dataset has none.
// points: out_dir/points.ply, holding the points that left the window during the run (the
// odometry's retired-point sink); finished here with the active ones.
nlohmann::json writeRunOutputs(const std::string& out_dir, const DatasetIndex& index,
                               const std::optional<Trajectory>& ground_truth,
                               const Odometry& odometry, const RunDescription& description,
                               PlyPointWriter& points);

// The stretch of recorded time the first `frames_processed` frames of the dataset cover: the
// span of their timestamps plus one frame period (each frame stands for one period; a single
// frame covers one period). 0 when the frame rate is unknown (fewer than two frames).
double processedSequenceSeconds(const DatasetIndex& index, size_t frames_processed);

// The human-readable lines `omnidso run` and `make demo` print.
void printRunSummary(std::ostream& os, const nlohmann::json& summary);

}  // namespace omnidso::cli
