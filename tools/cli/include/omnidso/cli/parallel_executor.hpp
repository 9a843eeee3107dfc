#pragma once
// --executor parallel: the pending runs as a job list for GNU parallel, e.g. over a few
// workstations that share a file system (--parallel-args "--sshloginfile hosts"):
//   parallel --jobs J --joblog OUT/parallel/submission-K/joblog.tsv ARGS :::: jobs.txt
// Line i of jobs.txt is the `omnidso ablate-task … -- omnidso run …` command of one run
// (ablation_task.hpp), with absolute paths. A job that GNU parallel saw end without a
// result.json (killed by its --timeout, ssh failing, …) gets the joblog's exit value and
// signal as its cluster.json reason, and is run again by the next invocation. `parallel` is
// found on PATH.

#include <memory>
#include <omnidso/cli/ablation_executor.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

struct ParallelOptions {
  std::vector<std::string> arguments;  // --parallel-args, split into words
  bool dry_run = false;                // only write jobs.txt
};

std::unique_ptr<AblationExecutor> makeParallelExecutor(const ParallelOptions& options);

}  // namespace omnidso::cli
