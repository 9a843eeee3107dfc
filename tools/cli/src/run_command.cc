// `omnidso run`: the odometry over a dataset (TUM, ASL, KITTI). Frames are read, corrected
// photometrically (pcalib.txt, vignette.png), rectified when the camera has distortion or a
// pinhole crop is asked for (the paper's "DSO with the pinhole model" baseline), and fed to
// omnidso::Odometry (dataset_runner.cc); the outputs are written by run_outputs.cc.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/cli/dataset_vignette.hpp>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/cli/progress.hpp>
#include <omnidso/cli/run_outputs.hpp>
#include <omnidso/cli/staged_directory.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/synth/dataset_loading.hpp>

namespace omnidso::cli {
namespace {

struct RunArguments {
  std::string dataset;
  std::string out;
  std::string camera_model = "native";
  std::string calib;
  int keyframes = 7;
  int points = 2000;
  bool no_intrinsics_opt = false;
  std::uint64_t seed = 0;
  int threads = 1;
  int compute_threads = 0;  // 0: the hardware threads, up to 8 (deterministic mode); 1 (real-time)
  int max_frames = 0;
  std::string residuals = "analytic";
  bool force = false;
  bool quiet = false;
  bool json = false;
  std::string config;
  std::vector<std::string> settings;  // NAME=VALUE, applied after --config
  double playback_speed = 1.0;
  bool skip_missing = false;  // drop frames whose images are missing instead of refusing
  bool no_prefetch = false;
  bool no_vignette_estimation = false;
};

void refuseToOverwrite(const std::string& out, bool force) {
  namespace fs = std::filesystem;
  if (out.empty()) throw Error("--out: empty path");
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error(out + ": exists and is not a directory");
  if (fs::is_directory(out) && !fs::is_empty(out) && !force)
    throw Error(out + ": directory is not empty (pass --force to overwrite the run's files)");
}

void printProgress(size_t done, size_t total, const Odometry& odometry) {
  printProgressBar(done, total, "keyframes " + std::to_string(odometry.keyframes().size()));
}

void runOdometry(const RunArguments& args) {
  if (args.dataset.empty()) throw Error("DATASET: empty path");
  DatasetOpenOptions open_options;
  open_options.skip_missing_images = args.skip_missing;
  const DatasetIndex index = openDataset(args.dataset, open_options);
  for (const std::string& warning : index.warnings) std::cerr << "warning: " << warning << "\n";
  // Read before the run, so that a bad file is reported now and not after an hour's work:
  // every image header (truncated or foreign files; ~1 s for thousands) and the ground truth.
  verifyDatasetImages(index);
  std::optional<Trajectory> ground_truth;
  if (index.groundtruth_path) ground_truth = synth::cameraGroundTruth(index);
  parsePinholeCrop(args.camera_model);  // reject a bad option before touching --out
  DatasetRunOptions options;
  options.camera_model = args.camera_model;
  options.calib = args.calib;
  options.max_frames = static_cast<size_t>(std::max(0, args.max_frames));
  OdometryOptions& o = options.odometry;
  o.num_points = args.points;
  o.num_candidates = args.points;
  o.seed = args.seed;
  o.window.max_keyframes = args.keyframes;
  o.window.optimize_intrinsics = !args.no_intrinsics_opt;
  o.window.num_threads = args.threads;
  o.window.differentiation =
      args.residuals == "autodiff" ? DifferentiationMode::kAutodiff : DifferentiationMode::kAnalytic;
  o.tracker.num_threads = args.threads;
  o.realtime = args.threads > 1;  // mapping in its own thread (not repeatable bit for bit)
  // The real-time mode's two threads already take a core each: its steps stay sequential
  // unless asked.
  o.compute_threads = args.compute_threads > 0 ? args.compute_threads
                      : o.realtime             ? 1
                                               : defaultComputeThreads();
  options.playback_speed = args.playback_speed;
  options.prefetch = !args.no_prefetch;
  options.estimate_vignette = !args.no_vignette_estimation;
  const std::string photometric_note = applyPhotometricMode(index, &o);  // before the user's
  const std::string pattern_note = applyCropPatternSpread(index, options, &o);  // likewise
  const int crop_pattern_spread = o.pattern_spread;
  const double view_width_deg = viewWidthDeg(index, options);
  const std::string intrinsics_note = applyIntrinsicsPrior(view_width_deg, &o);  // likewise
  const std::string view_note =
      applyViewProfile(view_width_deg, exposureTimesKnown(index), &o);  // likewise
  const WindowOptions profile_window = o.window;
  const std::string tracking_note = applyNarrowViewTracking(view_width_deg, &o);  // likewise
  const int profile_reference_neighbours = o.reference_depths.neighbours;
  if (!args.config.empty()) applyOdometryConfigFile(o, args.config);
  for (const std::string& s : args.settings) applyOdometrySettingAssignment(o, s);
  refuseToOverwrite(args.out, args.force);  // after every option has been checked
  StagedDirectory out(args.out);              // --out changes only when the run completes
  PlyPointWriter points(out.path() + "/points.ply");  // the map goes to disk as it is made
  options.retired_point_sink = [&points](const OdometryPoint& p) { points.add(p); };
  if (!args.quiet && ::isatty(STDERR_FILENO))
    options.progress = [](size_t done, size_t total, const Odometry& odometry) {
      if (done % 10 == 0 || done == total) printProgress(done, total, odometry);
    };
  const DatasetRun run = runOdometryOnDataset(index, options);
  // After the run, so that a bad input still gets its one line of error and nothing else.
  if (!photometric_note.empty() && o.window.affine_prior_weight_a == 0.0 &&
      o.tracker.affine_prior_weight_a == 0.0)
    std::cerr << "note: " << photometric_note << "\n";
  if (!pattern_note.empty() && o.pattern_spread == crop_pattern_spread)
    std::cerr << "note: " << pattern_note << "\n";
  if (!intrinsics_note.empty() && o.window.intrinsics_prior_weight == 0.0 &&
      o.window.optimize_intrinsics)
    std::cerr << "note: " << intrinsics_note << "\n";
  if (!view_note.empty() &&
      o.window.central_difference_gradients == profile_window.central_difference_gradients &&
      o.window.max_iterations == profile_window.max_iterations)
    std::cerr << "note: " << view_note << "\n";
  if (!tracking_note.empty() && o.reference_depths.neighbours == profile_reference_neighbours)
    std::cerr << "note: " << tracking_note << "\n";
  if (run.vignette_estimate) {
    std::cerr << "note: " << vignetteEstimateNote(*run.vignette_estimate) << "\n";
    if (run.vignette_estimate->valid)
      writeVignette(out.path() + "/vignette_estimated.png",
                    run.vignette_estimate->map(run.source.width(), run.source.height()));
  }
  const Odometry& odometry = *run.odometry;
  const size_t total = run.frames_processed;
  RunDescription description;
  description.dataset = args.dataset;
  description.camera_model_option = args.camera_model;
  description.source_camera = run.source.modelName();
  description.odometry_camera = run.camera.modelName();
  description.keyframes = args.keyframes;
  description.points = args.points;
  description.optimize_intrinsics = !args.no_intrinsics_opt;
  description.seed = args.seed;
  description.threads = args.threads;
  description.compute_threads = o.compute_threads;
  description.residuals = args.residuals;
  description.frames_processed = total;
  description.wall_s = run.wall_s;
  description.settings = odometrySettingsJson(o);
  description.view = {{"width_deg", view_width_deg},
                      {"narrow", view_width_deg < kNarrowViewBelowDeg},
                      {"narrow_view_window", !view_note.empty()},
                      {"narrow_view_tracking", !tracking_note.empty()}};
  if (run.vignette_estimate) description.vignette_estimate = vignetteEstimateJson(*run.vignette_estimate);
  const nlohmann::json summary =
      writeRunOutputs(out.path(), index, ground_truth, odometry, description, points);
  out.commit();
  if (args.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    printRunSummary(std::cout, summary);
  }
}

}  // namespace

void registerRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArguments>();
  CLI::App* cmd = app.add_subcommand(
      "run", "run the odometry on a dataset (TUM, ASL or KITTI odometry layout)");
  cmd->add_option("DATASET", args->dataset, "dataset directory")->required();
  cmd->add_option("--out", args->out, "output directory (refused when non-empty unless --force)")
      ->required();
  cmd->add_option("--camera-model", args->camera_model,
                  "native (the dataset's model, undistorted) or pinhole-crop:FOV_DEG")
      ->capture_default_str();
  cmd->add_option("--calib", args->calib, "calibration file overriding the dataset's")
      ->check(CLI::ExistingFile);
  cmd->add_option("--keyframes", args->keyframes, "active keyframes N_f")
      ->check(CLI::Range(2, 64))
      ->capture_default_str();
  cmd->add_option("--points", args->points, "active points aimed at")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_flag("--no-intrinsics-opt", args->no_intrinsics_opt,
                "keep the intrinsics fixed in the window optimisation");
  cmd->add_option("--seed", args->seed, "seed of the pixel selection")->capture_default_str();
  cmd->add_option("--threads", args->threads,
                  "1: deterministic single-threaded mode; N > 1: real-time mode (mapping in its "
                  "own thread, Ceres with N threads)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--compute-threads", args->compute_threads,
                  "threads for the data-parallel steps (epipolar search, the window's "
                  "evaluation, candidate refinement and selection, the initialiser's rotation "
                  "search); the trajectory is the same bit for bit "
                  "for any count. 0: the hardware threads (at most 8) in the deterministic mode, 1 in the "
                  "real-time mode")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->add_option("--playback-speed", args->playback_speed,
                  "real-time mode: feed frames at this multiple of their recorded rate "
                  "(0 = as fast as possible)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--max-frames", args->max_frames, "stop after this many frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--residuals", args->residuals, "analytic | autodiff")
      ->check(CLI::IsMember({"analytic", "autodiff"}))
      ->capture_default_str();
  cmd->add_option("--config", args->config,
                  "YAML file of odometry settings (NAME: VALUE; docs/architecture.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", args->settings, "one odometry setting NAME=VALUE (repeatable; after --config)");
  cmd->add_flag("--force", args->force, "write into a non-empty --out");
  cmd->add_flag("--skip-missing", args->skip_missing,
                "drop the frames whose listed image is missing (default: refuse the dataset)");
  cmd->add_flag("--no-prefetch", args->no_prefetch,
                "read each image when it is due instead of the next one while a frame is "
                "processed (the same trajectory; for timing the odometry alone)");
  cmd->add_flag("--no-vignette-estimation", args->no_vignette_estimation,
                "without vignette.png, take the images as unvignetted instead of estimating the "
                "vignette from the frames");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  cmd->callback([args] { runOdometry(*args); });
}

}  // namespace omnidso::cli
