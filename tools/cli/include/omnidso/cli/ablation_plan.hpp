#pragma once
// The grid of `omnidso ablate`: every dataset × camera model × N_f is a cell, and every
// cell is run `runs` times as `omnidso run` with seeds base_seed + 0 … runs − 1 (run k uses
// base_seed + k − 1 in every cell, so cells are compared on the same seeds).
//
// Layout of the output directory OUT:
//   OUT/ablation.json              marks OUT as an ablation directory (settings, cells)
//   OUT/runs/CELL/runK/            `omnidso run --out` of run K (1-based) of cell CELL,
//                                  with log.txt (its stdout and stderr) and result.json
//                                  (written atomically once the run has finished)
// CELL is DATASET__CAMERA__kfN with every character outside [A-Za-z0-9._-] replaced by '-'.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

// Options passed through to every `omnidso run`.
struct RunPassThrough {
  int points = 2000;
  int max_frames = 0;  // 0: all
  bool no_intrinsics_opt = false;
  bool no_vignette_estimation = false;
  int threads = 1;
  std::string residuals = "analytic";
  std::string config;                 // --config FILE (odometry settings), empty: none
  std::vector<std::string> settings;  // --set NAME=VALUE, in order
};

struct AblationSpec {
  std::vector<std::string> datasets;  // directories; their names label the tables
  std::vector<std::string> camera_models;
  std::vector<int> keyframes;  // the first is the reference of Table IV
  int runs = 5;
  std::uint64_t base_seed = 0;
  RunPassThrough pass_through;
};

struct AblationCell {
  std::string dataset_name;  // the dataset directory's name
  std::string dataset_path;
  std::string camera_model;  // native | pinhole-crop:FOV_DEG
  int keyframes = 7;

  std::string id() const;      // the directory name CELL
  std::string method() const;  // "native Kf7": camera model and N_f, for legends
};

struct PlannedRun {
  std::size_t cell = 0;  // index into AblationPlan::cells
  int run = 1;           // 1-based
  std::uint64_t seed = 0;
  std::string directory;               // OUT/runs/CELL/runK
  std::vector<std::string> arguments;  // of `omnidso run`, without the executable
  nlohmann::json settings;             // what the result depends on; compared when resuming
};

struct AblationPlan {
  std::vector<AblationCell> cells;  // dataset-major, then camera model, then N_f
  std::vector<PlannedRun> runs;     // cell-major, then run
};

// Checks the spec (non-empty lists without duplicates, valid camera models, 2 ≤ N_f ≤ 64,
// runs ≥ 1, distinct dataset names) and throws omnidso::Error naming the option otherwise.
AblationPlan planAblation(const AblationSpec& spec, const std::string& out_dir);

// "a,b,c" → {"a", "b", "c"} (empty items are an error naming the option).
std::vector<std::string> splitList(const std::string& text, const std::string& option);
std::vector<int> parseIntegerList(const std::string& text, const std::string& option);

// Makes OUT ready: creates it, or accepts an existing empty directory or one that holds
// ablation.json (a resumed ablation). Anything else — a file, a directory with other
// content — throws, so that nothing of the user's is overwritten.
void prepareAblationDirectory(const std::string& out_dir);
inline constexpr const char* kAblationMarker = "ablation.json";

}  // namespace omnidso::cli
