// `omnidso synth`: renders a synthetic fisheye sequence with ground truth into a dataset
// (TUM layout). The renderer and writer live in omnidso::synth; this file parses options.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/progress.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/synth/dataset_writer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso::cli {
namespace {

struct SynthArguments {
  std::string preset = "room185";
  std::string out;
  int frames = 0;
  std::string camera_model;
  double fov_deg = 0;
  std::string size;
  std::string trajectory;
  std::vector<std::string> posters;
  std::uint64_t seed = 1;
  int threads = 2;
  int samples = 0;
  int motion_blur = 0;
  bool force = false;
  bool quiet = false;
};

// "WxH" → (W, H); throws omnidso::Error naming the option otherwise. The upper bound keeps a
// mistyped size from asking for more memory than a machine has (8192² floats: 256 MB).
std::pair<int, int> parseSize(const std::string& text) {
  constexpr int kMaxSide = 8192;
  int width = 0;
  int height = 0;
  char x = 0;
  char rest = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' ||
      width < 8 || height < 8 || width > kMaxSide || height > kMaxSide) {
    throw Error("--size: expected WxH with 8 <= W, H <= " + std::to_string(kMaxSide) +
                " (e.g. 480x480), got '" + text + "'");
  }
  return {width, height};
}

void printProgress(int done, int total, double seconds) {
  printProgressBar(done, total, fmt::format("{:.1f} frames/s", seconds > 0 ? done / seconds : 0.0));
}

void runSynth(const SynthArguments& args, const CLI::App& cmd) {
  synth::SyntheticSequenceConfig config = synth::presetConfig(args.preset);
  if (cmd.count("--camera-model")) {
    config.camera_model = args.camera_model;
    // A pinhole camera cannot see 180°: without --fov it takes the ablation's 90°.
    if (canonicalCameraModelName(args.camera_model) == "pinhole" && !cmd.count("--fov")) {
      config.fov_deg = 90.0;
    }
  }
  if (cmd.count("--fov")) config.fov_deg = args.fov_deg;
  if (cmd.count("--frames")) config.frames = args.frames;
  if (cmd.count("--size")) std::tie(config.width, config.height) = parseSize(args.size);
  if (cmd.count("--trajectory")) config.trajectory_file = args.trajectory;
  if (cmd.count("--seed")) config.seed = args.seed;
  config.room.poster_images = args.posters;
  if (cmd.count("--samples")) config.samples_per_axis = args.samples;
  if (cmd.count("--motion-blur")) config.motion_blur_samples = args.motion_blur;
  config.threads = args.threads;

  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  synth::SyntheticSequence sequence(config);
  synth::DatasetWriteOptions options;
  options.overwrite = args.force;
  const auto render_start = std::chrono::steady_clock::now();
  if (!args.quiet && ::isatty(STDERR_FILENO)) {
    options.progress = [&render_start](int done, int total) {
      printProgress(done, total,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                  render_start)
                        .count());
    };
  }
  synth::writeSyntheticDataset(sequence, args.out, options);
  const double render_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - render_start).count();
  std::cout << fmt::format(
      "wrote {} frames {}x{} ({}, maximum field of view {:.1f} deg) to {} in {:.1f} s "
      "({:.1f} frames/s rendering)\n",
      sequence.numFrames(), config.width, config.height, sequence.camera().modelName(),
      maximumFovDeg(sequence.camera()), args.out, elapsed(),
      render_s > 0 ? sequence.numFrames() / render_s : 0.0);
}

}  // namespace

void registerSynthCommand(CLI::App& app) {
  auto args = std::make_shared<SynthArguments>();
  CLI::App* cmd = app.add_subcommand(
      "synth", "render a synthetic sequence with ground truth as a TUM-layout dataset");
  cmd->add_option("--preset", args->preset, "room185 | room185_long | room_pinhole90")
      ->check(CLI::IsMember(synth::presetNames()))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "output directory (must be empty unless --force)")
      ->required();
  cmd->add_option("--frames", args->frames, "number of frames (default: the preset's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--camera-model", args->camera_model, "camera model (default: the preset's)")
      ->check(CLI::IsMember({"ucm", "pinhole", "eucm", "ds", "kb", "kb4", "fov", "atan"}));
  cmd->add_option("--fov", args->fov_deg, "field of view in degrees across the image circle")
      ->check(CLI::Range(1.0, 359.0));
  cmd->add_option("--size", args->size, "image size WxH (default 480x480)");
  cmd->add_option("--trajectory", args->trajectory,
                  "TUM-format body trajectory to follow (default: procedural hand-held)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--poster", args->posters,
                  "image file to hang on the walls as a texture (repeatable)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--seed", args->seed, "seed of textures, motion and noise")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "render threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--samples", args->samples, "samples per pixel and axis (n x n, default 2)")
      ->check(CLI::Range(1, 8));
  cmd->add_option("--motion-blur", args->motion_blur,
                  "poses spread over the exposure (1 = no motion blur)")
      ->check(CLI::Range(1, 16));
  cmd->add_flag("--force", args->force, "overwrite the dataset files in a non-empty --out");
  cmd->add_flag("--quiet", args->quiet, "no progress bar");
  cmd->callback([args, cmd] { runSynth(*args, *cmd); });
}

}  // namespace omnidso::cli
