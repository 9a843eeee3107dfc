#pragma once
// What every executor of `omnidso ablate` prints while runs end: a line per finished run
//   [3/16] room_a native Kf5 run 2 (seed 1): ok, RMSE 0.0123 m (41.2 s)
// and, on a terminal, the progress bar (progress.hpp) under it.

#include <cstddef>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/ablation_run_result.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

std::string runResultLine(const PlannedRun& run, const AblationCell& cell, const RunResult& r);

class RunProgress {
 public:
  RunProgress(std::size_t total, bool quiet);
  // Counts the run and prints its line; redraw() then puts the bar back.
  void finished(const PlannedRun& run, const AblationCell& cell, const RunResult& result);
  // The bar with `detail` after it (e.g. "running 2, failed 1"), on a terminal only.
  void redraw(const std::string& detail);
  std::size_t done() const { return done_; }
  std::size_t failed() const { return failed_; }

 private:
  std::size_t total_, done_ = 0, failed_ = 0;
  bool quiet_, bar_;
};

// For the executors that learn of a run's end from its files: prints each run of `unreported`
// (indices into plan.runs) whose result.json has appeared — or every one when `all_ended`,
// then with its cluster.json reason or as missing — and drops it from the list.
void reportEndedRuns(const AblationPlan& plan, std::vector<size_t>& unreported, bool all_ended,
                     RunProgress& progress);

}  // namespace omnidso::cli
