#pragma once
// One run of an ablation as a task of another scheduler (Slurm, GNU parallel):
//   OMNIDSO ablate-task --timeout S RUN_DIR -- OMNIDSO run DATASET --out RUN_DIR …
// runs the `omnidso run` command line that the local executor would start, with
// RUN_DIR/log.txt as its output and the same timeout, and then writes RUN_DIR/result.json
// exactly as the local executor does (ablation_run_result.hpp). What result.json records
// besides the process — run number, seed, settings — comes from RUN_DIR/planned.json, written
// when the task is planned. A run that already has a result.json is left alone (the task
// exits at once), so that nothing of a finished run is overwritten by a resubmission.
//
// When the task is told to stop (SIGTERM, SIGINT or SIGHUP: scancel, Slurm's time limit,
// GNU parallel's --timeout or Ctrl-C) it kills the run and writes no result.json: the run is
// not finished, the cluster's reason is collected by the executor instead. So does a run
// killed by SIGKILL inside a Slurm job (the OOM killer of its cgroup).

#include <omnidso/cli/ablation_plan.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

inline constexpr const char* kPlannedRunFile = "planned.json";

void writePlannedRun(const PlannedRun& run);
// Throws omnidso::Error naming RUN_DIR/planned.json when it is missing or unreadable.
PlannedRun readPlannedRun(const std::string& run_directory);

// argv of the task, starting with `executable`.
std::vector<std::string> taskArguments(const PlannedRun& run, const std::string& executable,
                                       double timeout_s);

}  // namespace omnidso::cli
