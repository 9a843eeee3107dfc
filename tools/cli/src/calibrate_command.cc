// `omnidso calibrate IMAGES_DIR --board COLSxROWS [--square M] [--models LIST] --out DIR
//  [--select MODEL] [--force] [--json]`.
// Thin: detection, the start, the adjustment and the outlier rules live in
// omnidso::cameras (calibration/); this file checks the arguments, runs them and writes DIR.
//
// DIR is written whole or not at all: everything goes into a sibling DIR.partial-<pid>
// that is renamed to DIR at the end (and removed on any error). An existing non-empty DIR
// is an error unless --force.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cli/calibration_outputs.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/error.hpp>
#include <unistd.h>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

const char* const kDefaultModels = "ucm,eucm,ds,kb4,fov,ucm-radtan,pinhole-radtan";

struct CalibrateArgs {
  std::string images;
  std::string board;
  double square = 1.0;
  std::string models = kDefaultModels;
  std::string out;
  std::string select;
  bool force = false;
  bool json = false;
};

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw fileError(path.string(), "write failed");
}

// Per model DIR/models/<name>/camchain.yaml (+ camera.txt where DSO has the model); the
// chosen model also as DIR/camchain.yaml (+ DIR/camera.txt).
void writeCalibrationFiles(const fs::path& dir, const CalibrationRun& run) {
  for (size_t i = 0; i < run.report.models.size(); ++i) {
    const Camera& camera = run.report.models[i].fit.camera;
    std::vector<fs::path> targets = {dir / "models" / camera.modelName()};
    if (i == run.chosen) targets.push_back(dir);
    for (const fs::path& target : targets) {
      fs::create_directories(target);
      saveKalibr((target / "camchain.yaml").string(), camera);
      if (!dsoCameraTxtKeyword(camera.modelName()).empty())
        saveDsoCameraTxt((target / "camera.txt").string(), camera);
    }
  }
}

void writeOutputs(const fs::path& dir, const CalibrationRun& run) {
  writeText(dir / "calibration.json", calibrationJson(run).dump(2) + "\n");
  writeText(dir / "comparison.md", comparisonMarkdown(run));
  writeCalibrationFiles(dir, run);
  writeCalibrationPlots(dir.string(), run);
}

void checkOutputFolder(const CalibrateArgs& args) {
  if (fs::exists(args.out) && !args.force &&
      (!fs::is_directory(args.out) || !fs::is_empty(args.out))) {
    throw fileError(args.out, "exists and is not an empty folder; pass --force to replace it");
  }
}

// Writes into a sibling partial folder, then moves it to args.out.
void publishOutputs(const CalibrateArgs& args, const CalibrationRun& run) {
  const fs::path out = fs::absolute(args.out).lexically_normal();
  const fs::path partial = out.string() + ".partial-" + std::to_string(::getpid());
  try {
    fs::create_directories(partial);
    writeOutputs(partial, run);
    if (fs::exists(out)) fs::remove_all(out);
    fs::rename(partial, out);
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(partial, ignored);
    throw;
  }
}

void runCalibrate(const CalibrateArgs& args) {
  CalibrationRun run;
  run.images_dir = args.images;
  run.board = parseBoardSpec(args.board, args.square);
  const std::vector<std::string> models = parseModelList(args.models);
  std::string select;
  if (!args.select.empty()) {
    select = canonicalCameraModelName(args.select);
    if (std::find(models.begin(), models.end(), select) == models.end())
      throw Error("--select " + args.select + ": not among --models " + args.models);
  }
  checkOutputFolder(args);

  run.detections = detectBoardsInFolder(args.images, run.board);
  run.report = calibrateModels(run.detections, run.board, models);
  run.chosen = run.report.selected;
  if (!select.empty()) {
    run.chosen_by_user = true;
    run.chosen = static_cast<size_t>(std::find(models.begin(), models.end(), select) -
                                     models.begin());
  }
  publishOutputs(args, run);

  if (args.json) {
    std::cout << calibrationJson(run).dump(2) << "\n";
    return;
  }
  for (const std::string& image : run.detections.without_board)
    std::cout << "no board: " << image << "\n";
  std::cout << comparisonMarkdown(run) << "\nwritten to " << args.out
            << " (calibration.json, comparison.md, camchain.yaml"
            << (dsoCameraTxtKeyword(run.report.models[run.chosen].fit.camera.modelName()).empty()
                    ? ""
                    : ", camera.txt")
            << ", models/, PNGs)\n";
}

}  // namespace

void registerCalibrateCommand(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Fit camera models to chessboard images and compare them");
  cmd->add_option("IMAGES_DIR", args->images, "Folder of chessboard images (one camera)")
      ->required();
  cmd->add_option("--board", args->board, "Inner corners COLSxROWS, e.g. 8x6")->required();
  cmd->add_option("--square", args->square, "Square side in metres (default 1)");
  cmd->add_option("--models", args->models,
                  std::string("Comma-separated models (default ") + kDefaultModels + ")");
  cmd->add_option("--out", args->out, "Output folder (created; must be empty or absent)")
      ->required();
  cmd->add_option("--select", args->select,
                  "Model written as DIR/camchain.yaml (default: the lowest BIC)");
  cmd->add_flag("--force", args->force, "Replace an existing --out folder");
  cmd->add_flag("--json", args->json, "Print calibration.json instead of the tables");
  cmd->callback([args] { runCalibrate(*args); });
}

}  // namespace omnidso::cli
