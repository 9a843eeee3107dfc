// `omnidso run`: the odometry over a dataset (TUM or ASL layout). Frames are read, corrected
// photometrically (pcalib.txt, vignette.png), rectified when the camera has distortion or a
// pinhole crop is asked for (the paper's "DSO with the pinhole model" baseline), and fed to
// omnidso::Odometry; the outputs are written by run_outputs.cc.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <omnidso/cameras/rectification.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/run_outputs.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/synth/dataset_loading.hpp>
#include <optional>

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
  int max_frames = 0;
  std::string residuals = "analytic";
  bool force = false;
  bool quiet = false;
  bool json = false;
};

// "native" or "pinhole-crop:FOV_DEG".
std::optional<double> parsePinholeCrop(const std::string& text) {
  if (text == "native") return std::nullopt;
  const std::string prefix = "pinhole-crop:";
  if (text.rfind(prefix, 0) == 0) {
    try {
      size_t used = 0;
      const double fov = std::stod(text.substr(prefix.size()), &used);
      if (used == text.size() - prefix.size() && fov > 1.0 && fov < 179.0) return fov;
    } catch (const std::exception&) {
    }
  }
  throw Error("--camera-model: expected 'native' or 'pinhole-crop:FOV_DEG' with 1 < FOV < 179, got '" +
              text + "'");
}

void refuseToOverwrite(const std::string& out, bool force) {
  namespace fs = std::filesystem;
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error(out + ": exists and is not a directory");
  if (fs::is_directory(out) && !fs::is_empty(out) && !force)
    throw Error(out + ": directory is not empty (pass --force to overwrite the run's files)");
  fs::create_directories(out);
}

void printProgress(size_t done, size_t total, const Odometry& odometry) {
  const int width = 40;
  const int filled = total ? static_cast<int>(done * width / total) : width;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu  keyframes %zu", std::string(filled, '#').c_str(),
               std::string(width - filled, '.').c_str(), done, total,
               odometry.keyframes().size());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

void runOdometry(const RunArguments& args) {
  const DatasetIndex index = openDataset(args.dataset);
  const Camera source = synth::datasetCamera(index, args.calib);
  const std::optional<double> crop_fov = parsePinholeCrop(args.camera_model);
  refuseToOverwrite(args.out, args.force);

  // The odometry's camera, and the map from the raw images to it when they differ.
  Camera camera = source.undistortedModel();
  if (crop_fov) camera = pinholeForFov(*crop_fov, source.width(), source.height());
  std::optional<RectificationMap> rectification;
  Mask image_mask;
  if (crop_fov || source.hasDistortion()) {
    rectification = makeRectificationMap(source, camera);
    image_mask = validMask(*rectification);
  }
  const PhotometricCalibration photometric = PhotometricCalibration::fromFiles(
      index.pcalib_path.value_or(""), index.vignette_path.value_or(""));
  if (photometric.hasVignette()) photometric.checkImageSize(source.width(), source.height());

  OdometryOptions options;
  options.num_points = args.points;
  options.num_candidates = args.points;
  options.seed = args.seed;
  options.window.max_keyframes = args.keyframes;
  options.window.optimize_intrinsics = !args.no_intrinsics_opt;
  options.window.num_threads = args.threads;
  options.window.differentiation =
      args.residuals == "autodiff" ? DifferentiationMode::kAutodiff : DifferentiationMode::kAnalytic;
  options.tracker.num_threads = args.threads;
  Odometry odometry(camera, options, image_mask);

  const size_t total = args.max_frames > 0
                           ? std::min(index.frames.size(), static_cast<size_t>(args.max_frames))
                           : index.frames.size();
  const bool progress = !args.quiet && ::isatty(STDERR_FILENO);
  Stopwatch wall;
  for (size_t i = 0; i < total; ++i) {
    const DatasetFrame& frame = index.frames[i];
    const RawImage raw = readRawImage(frame.image_path);
    if (raw.pixels.width() != source.width() || raw.pixels.height() != source.height())
      throw Error(frame.image_path + ": image is " + std::to_string(raw.pixels.width()) + "x" +
                  std::to_string(raw.pixels.height()) + ", expected " +
                  std::to_string(source.width()) + "x" + std::to_string(source.height()) +
                  " (" + frame.index_file + ":" + std::to_string(frame.index_line) + ")");
    ImageF image = photometric.correct(raw);
    if (rectification) image = remap(image, *rectification);
    const double exposure = frame.exposure_ms > 0 ? frame.exposure_ms : 1.0;
    odometry.addFrame(image, frame.timestamp_s, exposure);
    if (progress && (i % 10 == 0 || i + 1 == total)) printProgress(i + 1, total, odometry);
  }
  RunDescription description;
  description.dataset = args.dataset;
  description.camera_model_option = args.camera_model;
  description.source_camera = source.modelName();
  description.odometry_camera = camera.modelName();
  description.keyframes = args.keyframes;
  description.points = args.points;
  description.optimize_intrinsics = !args.no_intrinsics_opt;
  description.seed = args.seed;
  description.threads = args.threads;
  description.residuals = args.residuals;
  description.frames_processed = total;
  description.wall_s = wall.elapsedMs() / 1000.0;
  const nlohmann::json summary = writeRunOutputs(args.out, index, odometry, description);
  if (args.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    printRunSummary(std::cout, summary);
  }
}

}  // namespace

void registerRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArguments>();
  CLI::App* cmd = app.add_subcommand("run", "run the odometry on a dataset (TUM or ASL layout)");
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
  cmd->add_option("--threads", args->threads, "Ceres threads (1 = deterministic)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--max-frames", args->max_frames, "stop after this many frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--residuals", args->residuals, "analytic | autodiff")
      ->check(CLI::IsMember({"analytic", "autodiff"}))
      ->capture_default_str();
  cmd->add_flag("--force", args->force, "write into a non-empty --out");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->add_flag("--json", args->json, "print the summary as JSON");
  cmd->callback([args] { runOdometry(*args); });
}

}  // namespace omnidso::cli
