#pragma once
// --executor slurm: the pending runs as one Slurm job array (slurm_script.hpp), submitted with
// `sbatch --parsable`, then followed — result.json files as runs end, `squeue` every
// poll interval — until no task is queued or running. A task that ended without a result.json
// (time limit, preemption, node failure, out of memory, scancel) gets the cluster's reason
// from `sacct` in its cluster.json (ablation_run_result.hpp), falling back on the last state
// squeue showed when accounting is off.
//
// Each submission K keeps its files in OUT/slurm/submission-K/: job.sh, runs.txt (line i: the
// run directory of array task i), job_id, and task-I.out (Slurm's output of task I).
// A submission is refused while an earlier one still has tasks queued or running, so that no
// run is performed twice at the same time. sbatch, squeue and sacct are found on PATH.

#include <memory>
#include <omnidso/cli/ablation_executor.hpp>
#include <omnidso/cli/slurm_script.hpp>
#include <string>

namespace omnidso::cli {

struct SlurmOptions {
  SlurmResources resources;
  bool wait = true;            // false: return once submitted (--no-wait)
  bool dry_run = false;        // only write the script (--dry-run)
  bool limit_running = false;  // %M = --jobs in --array (only when --jobs was given)
  double poll_interval_s = 15;
};

std::unique_ptr<AblationExecutor> makeSlurmExecutor(const SlurmOptions& options);

// For `--collect`: the cluster's reason for every run of a finished submission in OUT that has
// neither result.json nor cluster.json yet (submitted with --no-wait). Queries nothing when
// OUT holds no submission.
void recordSlurmFailures(const std::string& out_dir, const AblationPlan& plan,
                         const SlurmOptions& options);

}  // namespace omnidso::cli
