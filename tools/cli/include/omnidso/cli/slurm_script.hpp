#pragma once
// The job-array script of `omnidso ablate --executor slurm`: array task i runs the i-th
// pending run of the ablation — the same `omnidso run` command line the local executor starts,
// wrapped in `omnidso ablate-task` (ablation_task.hpp) so that it writes the run's result.json:
//
//   #!/bin/bash
//   #SBATCH --job-name=omnidso-ablate
//   #SBATCH --array=0-N%M          (N + 1 runs, at most M at a time; no %M when M = 0)
//   #SBATCH --output=OUT/slurm/submission-K/task-%a.out
//   #SBATCH --ntasks=1 --cpus-per-task=C [--partition --time --mem, each --slurm-arg]
//   case "$SLURM_ARRAY_TASK_ID" in 0) exec omnidso ablate-task … ;; … esac

#include <string>
#include <vector>

namespace omnidso::cli {

struct SlurmResources {
  std::string partition;           // --partition; empty: the cluster's default
  std::string time;                // --time (e.g. 2:00:00); empty: the partition's default
  int cpus = 1;                    // --cpus-per-task
  std::string mem;                 // --mem (e.g. 4G); empty: the cluster's default
  std::vector<std::string> extra;  // further sbatch options, one #SBATCH line each
};

// tasks[i]: argv of array task i. Throws omnidso::Error naming the option when a value cannot
// stand in an #SBATCH line (a line break; blanks in the output path).
std::string slurmArrayScript(const std::vector<std::vector<std::string>>& tasks,
                             const SlurmResources& resources, int max_running,
                             const std::string& output_directory);

}  // namespace omnidso::cli
