#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

std::optional<double> numberAt(const nlohmann::json& j, const nlohmann::json::json_pointer& p) {
  if (!j.contains(p) || !j.at(p).is_number()) return std::nullopt;
  return j.at(p).get<double>();
}

nlohmann::json optionalJson(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string lastLogLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    const size_t end = line.find_last_not_of(" \t\r");
    if (end != std::string::npos) last = line.substr(0, end + 1);
  }
  if (last.size() > 300) last = last.substr(0, 300) + "…";
  return last;
}

void readMetrics(const nlohmann::json& s, RunResult& r) {
  using P = nlohmann::json::json_pointer;
  r.rmse_m = numberAt(s, P("/ate/keyframe_ate/rmse_m"));
  r.rmse_percent_of_path = numberAt(s, P("/ate/keyframe_ate/rmse_percent_of_path"));
  r.scale_drift_percent =
      numberAt(s, P("/ate/keyframe_ate/scale_drift/percent_over_sequence"));
  r.tracking_ms = numberAt(s, P("/timing/tracking_ms_per_frame/mean"));
  r.mapping_ms = numberAt(s, P("/timing/mapping_ms_per_keyframe/mean"));
}

// A temporary file renamed, so that a reader never sees half of it.
void writeJsonAtomically(const fs::path& path, const nlohmann::json& j) {
  const fs::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << j.dump(2) << "\n";
    if (!out) throw Error(temporary.string() + ": cannot write");
  }
  fs::rename(temporary, path);
}

}  // namespace

std::optional<std::string> summaryFailure(const nlohmann::json& s) {
  if (!s.value("initialized", false)) {
    const std::string status = s.value("initialization_status", std::string());
    return "not initialised" + (status.empty() ? "" : ": " + status);
  }
  if (s.contains("events") && s["events"].is_array())
    for (const auto& event : s["events"])
      if (event.is_string() && event.get<std::string>().find("tracking lost") != std::string::npos)
        return "lost tracking (" + event.get<std::string>() + ")";
  const int segments = s.contains("counts") ? s["counts"].value("segments", 1) : 1;
  if (segments > 1) return fmt::format("lost tracking ({} trajectory segments)", segments);
  if (!s.contains("ate")) return std::string("no keyframe ATE in summary.json (no ground truth?)");
  const auto& ate = s["ate"].value("keyframe_ate", nlohmann::json::object());
  if (!ate.contains("rmse_m"))
    return "no keyframe ATE: " + ate.value("error", std::string("not computed"));
  return std::nullopt;
}

RunResult classifyRun(const PlannedRun& run, const ProcessOutcome& outcome) {
  RunResult r;
  r.run = run.run;
  r.seed = run.seed;
  r.settings = run.settings;
  r.wall_s = outcome.wall_s;
  const fs::path dir(run.directory);
  if (!outcome.succeeded()) {
    r.failure = outcome.describe();
    const std::string last = lastLogLine((dir / "log.txt").string());
    if (outcome.kind == ProcessOutcome::Kind::kExited && !last.empty()) r.failure += ": " + last;
    return r;
  }
  const fs::path summary_path = dir / "summary.json";
  std::ifstream in(summary_path);
  if (!in) {
    r.failure = "no summary.json although the run exited with status 0";
    return r;
  }
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    r.failure = std::string("summary.json unreadable: ") + e.what();
    return r;
  }
  readMetrics(summary, r);
  const std::optional<std::string> failure = summaryFailure(summary);
  r.ok = !failure;
  r.failure = failure.value_or("");
  return r;
}

nlohmann::json toJson(const RunResult& r) {
  return {{"run", r.run},
          {"seed", r.seed},
          {"status", r.ok ? "ok" : "failed"},
          {"failure", r.failure},
          {"wall_s", r.wall_s},
          {"rmse_m", optionalJson(r.rmse_m)},
          {"rmse_percent_of_path", optionalJson(r.rmse_percent_of_path)},
          {"scale_drift_percent", optionalJson(r.scale_drift_percent)},
          {"tracking_ms_per_frame", optionalJson(r.tracking_ms)},
          {"mapping_ms_per_keyframe", optionalJson(r.mapping_ms)},
          {"settings", r.settings}};
}

RunResult runResultFromJson(const nlohmann::json& j) {
  using P = nlohmann::json::json_pointer;
  RunResult r;
  r.run = j.at("run").get<int>();
  r.seed = j.at("seed").get<std::uint64_t>();
  r.ok = j.at("status").get<std::string>() == "ok";
  r.failure = j.value("failure", std::string());
  r.wall_s = j.value("wall_s", 0.0);
  r.rmse_m = numberAt(j, P("/rmse_m"));
  r.rmse_percent_of_path = numberAt(j, P("/rmse_percent_of_path"));
  r.scale_drift_percent = numberAt(j, P("/scale_drift_percent"));
  r.tracking_ms = numberAt(j, P("/tracking_ms_per_frame"));
  r.mapping_ms = numberAt(j, P("/mapping_ms_per_keyframe"));
  r.settings = j.at("settings");
  return r;
}

void writeRunResult(const std::string& run_directory, const RunResult& result) {
  writeJsonAtomically(fs::path(run_directory) / "result.json", toJson(result));
}

std::optional<RunResult> readFinishedRun(const PlannedRun& run) {
  const fs::path path = fs::path(run.directory) / "result.json";
  if (!fs::exists(path)) return std::nullopt;
  RunResult r;
  try {
    std::ifstream in(path);
    r = runResultFromJson(nlohmann::json::parse(in));
  } catch (const nlohmann::json::exception& e) {
    throw fileError(path.string(), std::string("unreadable (") + e.what() +
                                       "); remove the file to run this run again");
  }
  if (r.settings != run.settings) {
    std::string differences;
    for (const auto& [key, now] : run.settings.items()) {
      const nlohmann::json then = r.settings.value(key, nlohmann::json(nullptr));
      if (then != now)
        differences += fmt::format("{}{} {} there, {} now", differences.empty() ? "" : "; ", key,
                                   then.dump(), now.dump());
    }
    throw fileError(path.string(), "made with other settings (" + differences +
                                       "); use another --out, or that ablation's settings");
  }
  return r;
}

RunResult currentRunState(const PlannedRun& run) {
  if (std::optional<RunResult> finished = readFinishedRun(run)) return *finished;
  RunResult r;
  r.run = run.run;
  r.seed = run.seed;
  r.settings = run.settings;
  const fs::path path = fs::path(run.directory) / kClusterFailureFile;
  if (!fs::exists(path)) {
    r.missing = true;
    r.failure = "not finished";
    return r;
  }
  try {
    std::ifstream in(path);
    r.failure = nlohmann::json::parse(in).at("failure").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw fileError(path.string(), std::string("unreadable (") + e.what() +
                                       "); remove the file, the run is not finished either way");
  }
  return r;
}

void writeClusterFailure(const PlannedRun& run, const std::string& reason) {
  if (fs::exists(fs::path(run.directory) / "result.json")) return;
  fs::create_directories(run.directory);
  writeJsonAtomically(fs::path(run.directory) / kClusterFailureFile,
                      {{"failure", reason},
                       {"note", "the cluster ended this run; it is run again when resubmitted"}});
}

}  // namespace omnidso::cli
