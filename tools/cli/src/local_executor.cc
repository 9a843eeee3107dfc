// --executor local: every pending run as a child process of this one, --jobs at a time,
// killed after --timeout; result.json written as each ends (the resumable state).
#include <fmt/core.h>

#include <filesystem>
#include <omnidso/cli/ablation_executor.hpp>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/cli/run_progress.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

class LocalExecutor : public AblationExecutor {
 public:
  bool execute(const ExecutionRequest& request) override {
    const AblationPlan& plan = *request.plan;
    std::vector<ProcessSpec> specs;
    for (size_t i : request.pending) {
      const PlannedRun& run = plan.runs[i];
      fs::create_directories(run.directory);
      ProcessSpec spec{
          {request.executable}, (fs::path(run.directory) / "log.txt").string(), request.timeout_s};
      spec.argv.insert(spec.argv.end(), run.arguments.begin(), run.arguments.end());
      specs.push_back(std::move(spec));
    }
    RunProgress progress(specs.size(), request.quiet);
    size_t running = 0;
    auto detail = [&] { return fmt::format("running {}, failed {}", running, progress.failed()); };
    ProcessCallbacks callbacks;
    callbacks.started = [&](size_t) { ++running, progress.redraw(detail()); };
    callbacks.finished = [&](size_t k, const ProcessOutcome& outcome) {
      const PlannedRun& run = plan.runs[request.pending[k]];
      const RunResult r = classifyRun(run, outcome);
      writeRunResult(run.directory, r);
      --running;
      progress.finished(run, plan.cells[run.cell], r);
      progress.redraw(detail());
    };
    runProcesses(specs, request.jobs, callbacks);
    return true;
  }
};

}  // namespace

std::unique_ptr<AblationExecutor> makeLocalExecutor() { return std::make_unique<LocalExecutor>(); }

}  // namespace omnidso::cli
