#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <omnidso/cli/ablation_task.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace fs = std::filesystem;

void writePlannedRun(const PlannedRun& run) {
  fs::create_directories(run.directory);
  const fs::path path = fs::path(run.directory) / kPlannedRunFile;
  const nlohmann::json j = {{"run", run.run}, {"seed", run.seed}, {"settings", run.settings}};
  std::ofstream(path.string() + ".tmp") << j.dump(2) << "\n";
  fs::rename(path.string() + ".tmp", path);
}

PlannedRun readPlannedRun(const std::string& run_directory) {
  const fs::path path = fs::path(run_directory) / kPlannedRunFile;
  std::ifstream in(path);
  if (!in)
    throw fileError(path.string(),
                    "cannot read (written by omnidso ablate when it plans "
                    "the run; is RUN_DIR a run of an ablation?)");
  PlannedRun run;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    run.run = j.at("run").get<int>();
    run.seed = j.at("seed").get<std::uint64_t>();
    run.settings = j.at("settings");
  } catch (const nlohmann::json::exception& e) {
    throw fileError(path.string(), std::string("unreadable: ") + e.what());
  }
  run.directory = run_directory;
  return run;
}

std::vector<std::string> taskArguments(const PlannedRun& run, const std::string& executable,
                                       double timeout_s) {
  std::vector<std::string> argv = {
      executable,    "ablate-task", "--timeout", fmt::format("{:g}", timeout_s),
      run.directory, "--",          executable};
  argv.insert(argv.end(), run.arguments.begin(), run.arguments.end());
  return argv;
}

}  // namespace omnidso::cli
