#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iostream>
#include <map>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/ablation_task.hpp>
#include <omnidso/cli/command_output.hpp>
#include <omnidso/cli/parallel_executor.hpp>
#include <omnidso/cli/run_progress.hpp>
#include <omnidso/cli/shell_words.hpp>
#include <omnidso/core/error.hpp>
#include <sstream>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

// Joblog line "Seq Host Starttime JobRuntime Send Receive Exitval Signal Command" (tabs)
// → Seq (1-based line of jobs.txt) → a reason for a job that left no result.json.
std::map<size_t, std::string> joblogReasons(const fs::path& joblog) {
  std::map<size_t, std::string> reasons;
  std::ifstream in(joblog);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f(1);
    for (char c : line) {
      if (c == '\t')
        f.emplace_back();
      else
        f.back().push_back(c);
    }
    if (f.size() < 8) continue;
    try {
      reasons[std::stoul(f[0])] = fmt::format(
          "GNU parallel: exit value {}, signal {} (host {}, {} s; {})", f[6], f[7], f[1],
          f[3].substr(std::min(f[3].size(), f[3].find_first_not_of(' '))), joblog.string());
    } catch (const std::exception&) {
      continue;  // not a job line
    }
  }
  return reasons;
}

class ParallelExecutor : public AblationExecutor {
 public:
  explicit ParallelExecutor(ParallelOptions options) : o_(std::move(options)) {}

  bool execute(const ExecutionRequest& request) override {
    if (request.pending.empty()) return true;
    const AblationPlan& plan = *request.plan;
    int k = 1;
    while (fs::exists(fs::path(request.out_dir) / "parallel" / ("submission-" + std::to_string(k))))
      ++k;
    const fs::path dir =
        fs::path(request.out_dir) / "parallel" / ("submission-" + std::to_string(k));
    fs::create_directories(dir);
    {
      std::ofstream jobs(dir / "jobs.txt");
      for (size_t i : request.pending) {
        const PlannedRun& run = plan.runs[i];
        writePlannedRun(run);
        fs::remove(fs::path(run.directory) / kClusterFailureFile);
        jobs << shellCommandLine(taskArguments(run, request.executable, request.timeout_s)) << "\n";
      }
    }
    std::vector<std::string> argv = {"parallel", "--jobs", std::to_string(request.jobs), "--joblog",
                                     (dir / "joblog.tsv").string()};
    argv.insert(argv.end(), o_.arguments.begin(), o_.arguments.end());
    argv.insert(argv.end(), {"::::", (dir / "jobs.txt").string()});
    std::ofstream(dir / "command.txt") << shellCommandLine(argv) << "\n";
    if (o_.dry_run) {
      std::cerr << fmt::format("wrote {} ({} jobs); run them with: {}\n",
                               (dir / "jobs.txt").string(), request.pending.size(),
                               shellCommandLine(argv));
      return false;
    }
    std::future<CommandOutput> parallel = std::async(std::launch::async, runCommand, argv);
    std::vector<size_t> unreported = request.pending;
    RunProgress progress(unreported.size(), request.quiet);
    while (parallel.wait_for(std::chrono::seconds(1)) != std::future_status::ready) {
      reportEndedRuns(plan, unreported, false, progress);
      progress.redraw(fmt::format("GNU parallel, failed {}", progress.failed()));
    }
    const CommandOutput result = parallel.get();
    std::ofstream(dir / "parallel.log") << result.out << result.err;
    if (!result.started)
      throw Error("GNU parallel: " + result.error + " (apt-get install parallel)");
    reportEndedRuns(plan, unreported, false, progress);
    // Jobs that ended without a result.json; the ones parallel never started stay missing.
    const std::map<size_t, std::string> reasons = joblogReasons(dir / "joblog.tsv");
    for (size_t line = 1; line <= request.pending.size(); ++line) {
      const PlannedRun& run = plan.runs[request.pending[line - 1]];
      if (reasons.count(line)) writeClusterFailure(run, reasons.at(line));
    }
    reportEndedRuns(plan, unreported, true, progress);
    if (result.exit_code != 0 && !request.quiet)
      std::cerr << fmt::format("GNU parallel: {} (its output: {})\n", result.describe(),
                               (dir / "parallel.log").string());
    return true;
  }

 private:
  ParallelOptions o_;
};

}  // namespace

std::unique_ptr<AblationExecutor> makeParallelExecutor(const ParallelOptions& options) {
  return std::make_unique<ParallelExecutor>(options);
}

}  // namespace omnidso::cli
