#include <fmt/core.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <omnidso/cli/progress.hpp>
#include <omnidso/cli/run_progress.hpp>

namespace omnidso::cli {

std::string runResultLine(const PlannedRun& run, const AblationCell& cell, const RunResult& r) {
  const std::string what =
      fmt::format("{} {} run {} (seed {})", cell.dataset_name, cell.method(), run.run, run.seed);
  if (r.missing) return what + ": not finished";
  if (!r.ok) return fmt::format("{}: FAILED, {} ({:.1f} s)", what, r.failure, r.wall_s);
  return fmt::format("{}: ok, RMSE {:.4f} m ({:.1f} s)", what, r.rmse_m.value_or(0.0), r.wall_s);
}

RunProgress::RunProgress(std::size_t total, bool quiet)
    : total_(total), quiet_(quiet), bar_(!quiet && ::isatty(STDERR_FILENO)) {}

void RunProgress::finished(const PlannedRun& run, const AblationCell& cell,
                           const RunResult& result) {
  ++done_;
  failed_ += !result.ok;
  if (!quiet_) {
    if (bar_) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "[%zu/%zu] %s\n", done_, total_, runResultLine(run, cell, result).c_str());
  }
}

void RunProgress::redraw(const std::string& detail) {
  if (bar_) printProgressBar(done_, total_, detail);
}

void reportEndedRuns(const AblationPlan& plan, std::vector<size_t>& unreported, bool all_ended,
                     RunProgress& progress) {
  for (auto it = unreported.begin(); it != unreported.end();) {
    const PlannedRun& run = plan.runs[*it];
    if (!all_ended &&
        !std::filesystem::exists(std::filesystem::path(run.directory) / "result.json")) {
      ++it;
      continue;
    }
    progress.finished(run, plan.cells[run.cell], currentRunState(run));
    it = unreported.erase(it);
  }
}

}  // namespace omnidso::cli
