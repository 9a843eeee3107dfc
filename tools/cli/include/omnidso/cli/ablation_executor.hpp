#pragma once
// Who performs the runs of `omnidso ablate` (--executor):
//   local     the runs as child processes of this one, --jobs at a time (process_pool.hpp)
//   slurm     one Slurm job array, a task per run (slurm_executor.hpp)
//   parallel  GNU parallel over a job list, e.g. on several workstations (parallel_executor.hpp)
// Whichever it is, every run ends with the same OUT/runs/CELL/runK/result.json (or, when a
// cluster ended it, cluster.json), and the tables are built from those files alone — so an
// ablation can be started with one executor, collected with `--collect`, and resumed with
// another.

#include <memory>
#include <omnidso/cli/ablation_plan.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

struct ExecutionRequest {
  const AblationPlan* plan = nullptr;
  std::vector<size_t> pending;  // indices into plan->runs without a result.json
  std::string executable;       // absolute path of the omnidso that performs the runs
  std::string out_dir;          // absolute
  double timeout_s = 0;         // per run; 0: none
  int jobs = 1;                 // runs at a time
  bool quiet = false;
};

class AblationExecutor {
 public:
  virtual ~AblationExecutor() = default;
  // Performs (or hands over) the pending runs. Returns true when they have all ended, so that
  // the tables can be built now; false when they are left running (--no-wait, --dry-run).
  virtual bool execute(const ExecutionRequest& request) = 0;
};

std::unique_ptr<AblationExecutor> makeLocalExecutor();

}  // namespace omnidso::cli
