#include <fmt/core.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/cli/run_outputs.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <omnidso/core/scale_drift.hpp>
#include <omnidso/cli/scale_drift_json.hpp>
#include <omnidso/core/trajectory_io.hpp>

namespace omnidso::cli {
namespace {

struct Stats {
  double mean = 0.0, median = 0.0;
  size_t count = 0;
};

Stats stats(std::vector<double> v) {
  Stats s;
  s.count = v.size();
  if (v.empty()) return s;
  double sum = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  std::sort(v.begin(), v.end());
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  return s;
}

nlohmann::json toJson(const Stats& s) {
  return {{"mean", s.mean}, {"median", s.median}, {"count", s.count}};
}

nlohmann::json evaluateSegment(const Trajectory& gt, const Trajectory& est, double max_dt) {
  nlohmann::json j;
  try {
    EvaluationOptions options;
    options.alignment = AlignmentType::kSim3;
    options.max_dt = max_dt;
    const EvaluationResult r = evaluate(gt, est, options);
    const double length = pathLength(gt, est.front().timestamp, est.back().timestamp);
    j["rmse_m"] = r.ate.rmse;
    j["mean_m"] = r.ate.mean;
    j["median_m"] = r.ate.median;
    j["max_m"] = r.ate.max;
    j["matched"] = r.ate.count;
    j["gt_path_length_m"] = length;
    if (length > 0) j["rmse_percent_of_path"] = 100.0 * r.ate.rmse / length;
    j["sim3_scale"] = r.alignment.scale();
    if (const auto drift = computeScaleDriftDefaultWindow(gt, est, r))
      j["scale_drift"] = scaleDriftJson(*drift);
  } catch (const Error& e) {
    j["error"] = e.what();
  }
  return j;
}

void writeTum(const std::string& path, const Trajectory& t) { writeTrajectoryTum(path, t); }

}  // namespace

nlohmann::json writeRunOutputs(const std::string& out_dir, const DatasetIndex& index,
                               const std::optional<Trajectory>& ground_truth,
                               const Odometry& odometry, const RunDescription& d,
                               PlyPointWriter& points) {
  // Trajectories, per segment and all together.
  std::map<int, Trajectory> frames_by_segment, keyframes_by_segment;
  Trajectory all_frames, all_keyframes;
  for (const FrameRecord& f : odometry.frames()) {
    if (!f.tracked) continue;
    const StampedPose p{f.timestamp, odometry.framePose(f)};
    frames_by_segment[f.segment].push_back(p);
    all_frames.push_back(p);
  }
  for (const KeyframeRecord& k : odometry.keyframes()) {
    const StampedPose p{k.timestamp, k.T_world_cam};
    keyframes_by_segment[k.segment].push_back(p);
    all_keyframes.push_back(p);
  }
  writeTum(out_dir + "/frames.txt", all_frames);
  writeTum(out_dir + "/keyframes.txt", all_keyframes);

  points.finish(odometry);  // the retired points are on disk already; now the active ones
  // Tracking and search: every tracked frame after the first of its segment; mapping: every
  // keyframe that ran the window.
  std::vector<double> tracking_ms, search_ms, mapping_ms, activation_ms, window_ms, outliers_ms,
      marginalization_ms, selection_ms, window_and_marginalization_ms;
  {
    std::ofstream csv(out_dir + "/timing.csv");
    if (!csv) throw Error(out_dir + "/timing.csv: cannot write");
    csv << "frame,timestamp,tracked,keyframe,segment,tracking_ms,search_ms,mapping_ms,window_ms,"
           "marginalization_ms,activation_ms,outliers_ms,selection_ms\n";
    for (const FrameRecord& f : odometry.frames()) {
      const FrameTiming& t = f.timing;
      csv << fmt::format("{},{:.9f},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f}\n",
                         f.index, f.timestamp, f.tracked ? 1 : 0, f.is_keyframe ? 1 : 0,
                         f.segment, t.tracking_ms, t.search_ms, t.mapping_ms, t.window_ms,
                         t.marginalization_ms, t.activation_ms, t.outliers_ms, t.selection_ms);
      if (f.tracked && t.tracking_ms > 0) {
        tracking_ms.push_back(t.tracking_ms);
        search_ms.push_back(t.search_ms);
      }
      if (f.is_keyframe && t.mapping_ms > 0) mapping_ms.push_back(t.mapping_ms);
      // Keyframes made by tracking (the initialisation's pair has no separate stages).
      if (f.is_keyframe && t.window_ms > 0) {
        activation_ms.push_back(t.activation_ms);
        window_ms.push_back(t.window_ms);
        outliers_ms.push_back(t.outliers_ms);
        marginalization_ms.push_back(t.marginalization_ms);
        selection_ms.push_back(t.selection_ms);
        window_and_marginalization_ms.push_back(t.window_ms + t.marginalization_ms);
      }
    }
  }

  nlohmann::json s;
  s["settings"] = {{"dataset", d.dataset},
                   {"camera_model", d.camera_model_option},
                   {"dataset_camera", d.source_camera},
                   {"odometry_camera", d.odometry_camera},
                   {"keyframes", d.keyframes},
                   {"points", d.points},
                   {"optimize_intrinsics", d.optimize_intrinsics},
                   {"seed", d.seed},
                   {"threads", d.threads},
                   {"compute_threads", d.compute_threads},
                   {"residuals", d.residuals},
                   {"odometry", d.settings},
                   {"view", d.view}};
  // What the photometric model had to work with (dataset_runner.hpp, applyPhotometricMode):
  // the calibration files used (null: absent) and whether every frame had an exposure time.
  auto pathOrNull = [](const std::optional<std::string>& p) {
    return p ? nlohmann::json(*p) : nlohmann::json(nullptr);
  };
  s["settings"]["photometric"] = {{"exposure_times", exposureTimesKnown(index)},
                                  {"inverse_response", pathOrNull(index.pcalib_path)},
                                  {"vignette", pathOrNull(index.vignette_path)},
                                  {"vignette_estimate", d.vignette_estimate}};
  s["counts"] = {{"frames", d.frames_processed},
                 {"tracked_frames", all_frames.size()},
                 {"keyframes", all_keyframes.size()},
                 {"points", points.count()},
                 {"segments", frames_by_segment.size()}};
  s["timing"] = {{"tracking_ms_per_frame", toJson(stats(tracking_ms))},
                 {"search_ms_per_frame", toJson(stats(search_ms))},
                 {"mapping_ms_per_keyframe", toJson(stats(mapping_ms))},
                 {"activation_ms_per_keyframe", toJson(stats(activation_ms))},
                 {"window_ms_per_keyframe", toJson(stats(window_ms))},
                 {"outliers_ms_per_keyframe", toJson(stats(outliers_ms))},
                 {"marginalization_ms_per_keyframe", toJson(stats(marginalization_ms))},
                 {"selection_ms_per_keyframe", toJson(stats(selection_ms))},
                 {"window_and_marginalization_ms_per_keyframe",
                  toJson(stats(window_and_marginalization_ms))},
                 {"wall_s", d.wall_s}};
  // Real-time factor: recorded time ÷ wall time (> 1: faster than the camera).
  const double sequence_s = processedSequenceSeconds(index, d.frames_processed);
  s["timing"]["sequence_s"] = sequence_s;
  s["timing"]["real_time_factor"] =
      d.wall_s > 0 && sequence_s > 0 ? nlohmann::json(sequence_s / d.wall_s) : nlohmann::json();
  s["events"] = odometry.log();
  const Eigen::VectorXd intrinsics = odometry.intrinsics();
  s["intrinsics_final"] = std::vector<double>(intrinsics.data(), intrinsics.data() + intrinsics.size());
  s["initialized"] = !all_keyframes.empty();
  if (!odometry.initialized()) s["initialization_status"] = odometry.initializationStatus();

  if (ground_truth && !all_keyframes.empty()) {
    const Trajectory& gt = *ground_truth;
    const double rate = datasetFrameRate(index);
    const double max_dt = rate > 0 ? 0.5 / rate : 0.02;
    nlohmann::json segments = nlohmann::json::array();
    int best = -1;
    size_t best_count = 0;
    for (const auto& [seg, kfs] : keyframes_by_segment) {
      nlohmann::json j;
      j["segment"] = seg;
      j["keyframes"] = kfs.size();
      j["keyframe_ate"] = evaluateSegment(gt, kfs, max_dt);
      j["frame_ate"] = evaluateSegment(gt, frames_by_segment[seg], max_dt);
      if (kfs.size() > best_count) {
        best_count = kfs.size();
        best = static_cast<int>(segments.size());
      }
      segments.push_back(j);
    }
    s["ate_segments"] = segments;
    if (best >= 0) s["ate"] = segments[best];
  }
  std::ofstream summary(out_dir + "/summary.json");
  summary << s.dump(2) << "\n";
  if (!summary) throw Error(out_dir + "/summary.json: write failed");
  return s;
}

double processedSequenceSeconds(const DatasetIndex& index, size_t frames_processed) {
  const double rate = datasetFrameRate(index);
  const size_t n = std::min(frames_processed, index.frames.size());
  if (!(rate > 0) || n == 0) return 0.0;
  return index.frames[n - 1].timestamp_s - index.frames[0].timestamp_s + 1.0 / rate;
}

void printRunSummary(std::ostream& os, const nlohmann::json& s) {
  const auto& c = s["counts"];
  os << fmt::format("frames {}  tracked {}  keyframes {}  points {}  segments {}\n",
                    c["frames"].get<size_t>(), c["tracked_frames"].get<size_t>(),
                    c["keyframes"].get<size_t>(), c["points"].get<size_t>(),
                    c["segments"].get<size_t>());
  const auto& t = s["timing"];
  os << fmt::format("tracking  mean {:.1f} ms  median {:.1f} ms per frame\n",
                    t["tracking_ms_per_frame"]["mean"].get<double>(),
                    t["tracking_ms_per_frame"]["median"].get<double>());
  os << fmt::format("search    mean {:.1f} ms  median {:.1f} ms per frame (epipolar curves)\n",
                    t["search_ms_per_frame"]["mean"].get<double>(),
                    t["search_ms_per_frame"]["median"].get<double>());
  os << fmt::format("mapping   mean {:.1f} ms  median {:.1f} ms per keyframe\n",
                    t["mapping_ms_per_keyframe"]["mean"].get<double>(),
                    t["mapping_ms_per_keyframe"]["median"].get<double>());
  os << fmt::format("  of it (means) activation {:.1f}  window {:.1f}  outliers {:.1f}  "
                    "marginalisation and new candidates {:.1f}  tracking reference {:.1f} ms\n",
                    t["activation_ms_per_keyframe"]["mean"].get<double>(),
                    t["window_ms_per_keyframe"]["mean"].get<double>(),
                    t["outliers_ms_per_keyframe"]["mean"].get<double>(),
                    t["marginalization_ms_per_keyframe"]["mean"].get<double>(),
                    t["selection_ms_per_keyframe"]["mean"].get<double>());
  if (t.contains("real_time_factor") && t["real_time_factor"].is_number())
    os << fmt::format("wall      {:.1f} s for {:.1f} s of recording: {:.2f}× real time\n",
                      t["wall_s"].get<double>(), t["sequence_s"].get<double>(),
                      t["real_time_factor"].get<double>());
  for (const auto& e : s["events"]) os << "event: " << e.get<std::string>() << "\n";
  if (s.contains("initialization_status"))
    os << "not initialised: " << s["initialization_status"].get<std::string>() << "\n";
  if (s.contains("ate")) {
    const auto& a = s["ate"]["keyframe_ate"];
    if (a.contains("rmse_m")) {
      os << fmt::format("keyframe ATE (Sim(3)-aligned, segment {}): RMSE {:.4f} m = {:.3f} % of "
                        "the {:.2f} m path\n",
                        s["ate"]["segment"].get<int>(), a["rmse_m"].get<double>(),
                        a["rmse_percent_of_path"].is_number()
                            ? a["rmse_percent_of_path"].get<double>()
                            : 0.0,
                        a["gt_path_length_m"].get<double>());
      if (a.contains("scale_drift")) {
        const auto& d = a["scale_drift"];
        os << fmt::format("scale drift (window {:.2f} m): {:+.2f} % over the sequence, {:+.2f} % "
                          "per 10 m; local scale {:.3f} … {:.3f}\n",
                          d["window_m"].get<double>(), d["percent_over_sequence"].get<double>(),
                          d["percent_per_10m"].get<double>(), d["min_ratio"].get<double>(),
                          d["max_ratio"].get<double>());
      }
    } else {
      os << "keyframe ATE: " << a["error"].get<std::string>() << "\n";
    }
  }
}

}  // namespace omnidso::cli
