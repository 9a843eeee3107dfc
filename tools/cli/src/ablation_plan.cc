#include <fmt/core.h>

#include <cctype>
#include <filesystem>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/core/error.hpp>
#include <set>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

std::string safeName(const std::string& text) {
  std::string out = text;
  for (char& c : out) {
    const bool keep =
        std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    if (!keep) c = '-';
  }
  return out;
}

// "seq/" and "seq" both name "seq".
fs::path normalisedPath(const std::string& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  return p;
}

template <typename T>
void requireDistinct(const std::vector<T>& items, const std::string& option) {
  if (items.empty()) throw Error(option + ": the list is empty");
  std::set<T> seen;
  for (const T& item : items)
    if (!seen.insert(item).second)
      throw Error(fmt::format("{}: '{}' is listed twice", option, item));
}

std::vector<std::string> runArguments(const AblationCell& cell, const RunPassThrough& p,
                                      std::uint64_t seed, const std::string& directory) {
  std::vector<std::string> a = {"run", cell.dataset_path, "--out", directory, "--force", "--quiet"};
  const std::pair<const char*, std::string> options[] = {
      {"--camera-model", cell.camera_model},    {"--keyframes", std::to_string(cell.keyframes)},
      {"--seed", std::to_string(seed)},         {"--points", std::to_string(p.points)},
      {"--threads", std::to_string(p.threads)}, {"--residuals", p.residuals}};
  for (const auto& [name, value] : options) a.insert(a.end(), {name, value});
  if (p.max_frames > 0) a.insert(a.end(), {"--max-frames", std::to_string(p.max_frames)});
  if (p.no_intrinsics_opt) a.push_back("--no-intrinsics-opt");
  if (p.no_vignette_estimation) a.push_back("--no-vignette-estimation");
  if (!p.config.empty()) a.insert(a.end(), {"--config", p.config});
  for (const std::string& setting : p.settings) a.insert(a.end(), {"--set", setting});
  return a;
}

nlohmann::json runSettings(const AblationCell& cell, const RunPassThrough& p, std::uint64_t seed) {
  nlohmann::json j = {{"dataset", cell.dataset_name},
                      {"camera_model", cell.camera_model},
                      {"keyframes", cell.keyframes},
                      {"seed", seed},
                      {"points", p.points},
                      {"max_frames", p.max_frames},
                      {"optimize_intrinsics", !p.no_intrinsics_opt},
                      {"threads", p.threads},
                      {"residuals", p.residuals},
                      {"config", p.config},
                      {"settings", p.settings}};
  // Only when set, so that the runs of earlier ablations still match and resume.
  if (p.no_vignette_estimation) j["vignette_estimation"] = false;
  return j;
}

}  // namespace

std::string AblationCell::id() const {
  return safeName(dataset_name) + "__" + safeName(camera_model) + "__kf" +
         std::to_string(keyframes);
}

std::string AblationCell::method() const {
  return camera_model + " Kf" + std::to_string(keyframes);
}

std::vector<std::string> splitList(const std::string& text, const std::string& option) {
  std::vector<std::string> items;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? comma : comma - start);
    if (item.empty())
      throw Error(fmt::format("{}: expected a comma-separated list without empty items, got '{}'",
                              option, text));
    items.push_back(item);
    if (comma == std::string::npos) return items;
    start = comma + 1;
  }
}

std::vector<int> parseIntegerList(const std::string& text, const std::string& option) {
  std::vector<int> values;
  for (const std::string& item : splitList(text, option)) {
    size_t used = 0;
    int value = 0;
    try {
      value = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size())
      throw Error(fmt::format("{}: '{}' is not an integer (in '{}')", option, item, text));
    values.push_back(value);
  }
  return values;
}

AblationPlan planAblation(const AblationSpec& spec, const std::string& out_dir) {
  requireDistinct(spec.datasets, "--datasets");
  requireDistinct(spec.camera_models, "--camera-models");
  requireDistinct(spec.keyframes, "--keyframes");
  if (spec.runs < 1) throw Error(fmt::format("--runs: expected at least 1, got {}", spec.runs));
  for (const std::string& model : spec.camera_models) {
    try {
      parsePinholeCrop(model);
    } catch (const Error&) {
      throw Error(
          "--camera-models: expected 'native' or 'pinhole-crop:FOV_DEG' items with "
          "1 < FOV < 179, got '" +
          model + "'");
    }
  }
  for (int n : spec.keyframes)
    if (n < 2 || n > 64) throw Error(fmt::format("--keyframes: {} is outside [2, 64]", n));
  std::vector<std::string> names;
  for (const std::string& d : spec.datasets) names.push_back(normalisedPath(d).filename().string());
  for (size_t i = 0; i < names.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (names[i] == names[j])
        throw Error(
            fmt::format("--datasets: '{}' and '{}' have the same name '{}', which labels "
                        "the tables; rename one of the directories",
                        spec.datasets[j], spec.datasets[i], names[i]));

  AblationPlan plan;
  for (size_t d = 0; d < spec.datasets.size(); ++d)
    for (const std::string& model : spec.camera_models)
      for (int n : spec.keyframes)
        plan.cells.push_back({names[d], normalisedPath(spec.datasets[d]).string(), model, n});
  std::set<std::string> ids;
  for (const AblationCell& cell : plan.cells)
    if (!ids.insert(cell.id()).second)
      throw Error(
          fmt::format("--camera-models: two cells share the directory name '{}'", cell.id()));

  for (size_t c = 0; c < plan.cells.size(); ++c) {
    for (int k = 1; k <= spec.runs; ++k) {
      PlannedRun run;
      run.cell = c;
      run.run = k;
      run.seed = spec.base_seed + static_cast<std::uint64_t>(k - 1);
      run.directory =
          (fs::path(out_dir) / "runs" / plan.cells[c].id() / ("run" + std::to_string(k))).string();
      run.arguments = runArguments(plan.cells[c], spec.pass_through, run.seed, run.directory);
      run.settings = runSettings(plan.cells[c], spec.pass_through, run.seed);
      plan.runs.push_back(std::move(run));
    }
  }
  return plan;
}

void prepareAblationDirectory(const std::string& out_dir) {
  if (fs::exists(out_dir) && !fs::is_directory(out_dir))
    throw Error(out_dir + ": exists and is not a directory");
  if (fs::is_directory(out_dir) && !fs::is_empty(out_dir) &&
      !fs::exists(fs::path(out_dir) / kAblationMarker))
    throw Error(
        fmt::format("{}: directory is not empty and holds no {} (not an ablation "
                    "directory); choose a new --out",
                    out_dir, kAblationMarker));
  fs::create_directories(out_dir);
}

}  // namespace omnidso::cli
