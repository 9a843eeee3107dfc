#pragma once
// The outcome of one run of an ablation, kept in OUT/runs/CELL/runK/result.json.
//
// A run fails when its process could not start, exits non-zero, is killed (a crash) or
// exceeds the timeout; or when its summary.json is missing, reports no keyframe ATE (not
// initialised, too few keyframes) or shows lost tracking (an event "tracking lost", or more
// than one trajectory segment). Failed runs keep their reason; they never enter a median.
//
// result.json is written (atomically: a temporary file renamed) only after the run's process
// has ended, so its presence means "finished": a resumed ablation does not run it again.
//
// A run without result.json is not finished. When a cluster ended its task (Slurm's time
// limit, a preemption, a node failure, out of memory, scancel; GNU parallel's ssh failing),
// the executor keeps the cluster's reason in OUT/runs/CELL/runK/cluster.json: the run counts
// as failed with that reason, and a resubmission runs it again (the reason was not the
// method's). Without either file the run is missing.

#include <nlohmann/json.hpp>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/process_pool.hpp>
#include <optional>
#include <string>

namespace omnidso::cli {

struct RunResult {
  int run = 1;
  std::uint64_t seed = 0;
  bool ok = false;
  bool missing = false;  // not finished and no cluster reason: neither ok nor failed
  std::string failure;   // why, when !ok
  double wall_s = 0;
  // From summary.json when it has them (failed runs may too; they are not used).
  std::optional<double> rmse_m;  // keyframe ATE RMSE after Sim(3) alignment
  std::optional<double> rmse_percent_of_path;
  // Change of the local scale over the run, % (omnidso/core/scale_drift.hpp).
  std::optional<double> scale_drift_percent;
  std::optional<double> tracking_ms;  // mean per frame
  std::optional<double> mapping_ms;   // mean per keyframe
  nlohmann::json settings;            // PlannedRun::settings
};

// Why a summary.json counts as failed, or nullopt when it is a success.
std::optional<std::string> summaryFailure(const nlohmann::json& summary);

// The result of a finished process: reads DIR/summary.json, and the last line of DIR/log.txt
// for the reason of a non-zero exit.
RunResult classifyRun(const PlannedRun& run, const ProcessOutcome& outcome);

void writeRunResult(const std::string& run_directory, const RunResult& result);

// The result.json of a run finished earlier, or nullopt. Throws omnidso::Error when it was
// made with other settings (the ablation in OUT differs from the one asked for).
std::optional<RunResult> readFinishedRun(const PlannedRun& run);

// What is known of a run now: its result.json, else its cluster.json as a failure, else missing.
RunResult currentRunState(const PlannedRun& run);

// Keeps the cluster's reason for a run it ended (see above); never for a finished run.
void writeClusterFailure(const PlannedRun& run, const std::string& reason);
inline constexpr const char* kClusterFailureFile = "cluster.json";

nlohmann::json toJson(const RunResult& result);
RunResult runResultFromJson(const nlohmann::json& j);

}  // namespace omnidso::cli
