#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <omnidso/cli/ablation_manifest.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

nlohmann::json passThroughJson(const RunPassThrough& p) {
  return {{"points", p.points},
          {"max_frames", p.max_frames},
          {"no_intrinsics_opt", p.no_intrinsics_opt},
          {"no_vignette_estimation", p.no_vignette_estimation},
          {"threads", p.threads},
          {"residuals", p.residuals},
          {"config", p.config},
          {"settings", p.settings}};
}

RunPassThrough passThroughFromJson(const nlohmann::json& j) {
  RunPassThrough p;
  p.points = j.at("points").get<int>();
  p.max_frames = j.at("max_frames").get<int>();
  p.no_intrinsics_opt = j.at("no_intrinsics_opt").get<bool>();
  p.no_vignette_estimation = j.value("no_vignette_estimation", false);  // older manifests: off
  p.threads = j.at("threads").get<int>();
  p.residuals = j.at("residuals").get<std::string>();
  p.config = j.at("config").get<std::string>();
  p.settings = j.at("settings").get<std::vector<std::string>>();
  return p;
}

}  // namespace

void writeAblationManifest(const std::string& out_dir, const AblationPlan& plan,
                           const AblationManifest& m) {
  nlohmann::json cells = nlohmann::json::array();
  for (const AblationCell& c : plan.cells)
    cells.push_back({{"id", c.id()},
                     {"dataset", c.dataset_name},
                     {"dataset_path", c.dataset_path},
                     {"camera_model", c.camera_model},
                     {"keyframes", c.keyframes}});
  nlohmann::json datasets = nlohmann::json::array();
  for (size_t c = 0; c < plan.cells.size();
       c += m.spec.camera_models.size() * m.spec.keyframes.size())
    datasets.push_back(plan.cells[c].dataset_path);
  const nlohmann::json manifest = {
      {"omnidso_ablation", 1},
      {"runs_per_cell", m.spec.runs},
      {"base_seed", m.spec.base_seed},
      {"timeout_s", m.timeout_s},
      {"jobs", m.jobs},
      {"grid",
       {{"datasets", datasets},
        {"camera_models", m.spec.camera_models},
        {"keyframes", m.spec.keyframes},
        {"run_options", passThroughJson(m.spec.pass_through)}}},
      {"cells", cells},
      {"note", "written by omnidso ablate; runs with a result.json are not run again"}};
  const fs::path path = fs::path(out_dir) / kAblationMarker;
  std::ofstream(path.string() + ".tmp") << manifest.dump(2) << "\n";
  fs::rename(path.string() + ".tmp", path);
}

AblationManifest readAblationManifest(const std::string& out_dir) {
  const fs::path path = fs::path(out_dir) / kAblationMarker;
  std::ifstream in(path);
  if (!in) throw fileError(path.string(), "cannot read (is --out an ablation directory?)");
  AblationManifest m;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.contains("grid"))
      throw fileError(path.string(),
                      "records no grid (written by an older omnidso); run the original "
                      "`omnidso ablate` command once more instead of --collect");
    const nlohmann::json& grid = j.at("grid");
    m.spec.datasets = grid.at("datasets").get<std::vector<std::string>>();
    m.spec.camera_models = grid.at("camera_models").get<std::vector<std::string>>();
    m.spec.keyframes = grid.at("keyframes").get<std::vector<int>>();
    m.spec.pass_through = passThroughFromJson(grid.at("run_options"));
    m.spec.runs = j.at("runs_per_cell").get<int>();
    m.spec.base_seed = j.at("base_seed").get<std::uint64_t>();
    m.timeout_s = j.at("timeout_s").get<double>();
    m.jobs = j.at("jobs").get<int>();
  } catch (const nlohmann::json::exception& e) {
    throw fileError(path.string(), std::string("unreadable: ") + e.what());
  }
  return m;
}

}  // namespace omnidso::cli
