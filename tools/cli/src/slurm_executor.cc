#include <fmt/core.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/ablation_task.hpp>
#include <omnidso/cli/command_output.hpp>
#include <omnidso/cli/run_progress.hpp>
#include <omnidso/cli/slurm_accounting.hpp>
#include <omnidso/cli/slurm_executor.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Submission {
  fs::path dir;                       // OUT/slurm/submission-K
  std::string job_id;                 // empty: written with --dry-run, never submitted
  std::vector<std::string> run_dirs;  // of array tasks 0, 1, …
};

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// OUT/slurm/submission-K for K = 1, 2, … in order.
std::vector<Submission> submissions(const std::string& out_dir) {
  std::vector<Submission> found;
  for (int k = 1;; ++k) {
    const fs::path dir = fs::path(out_dir) / "slurm" / ("submission-" + std::to_string(k));
    if (!fs::is_directory(dir)) return found;
    Submission s{dir, {}, {}};
    std::string id = readText(dir / "job_id");
    s.job_id = id.substr(0, id.find_first_of("\n"));
    std::istringstream runs(readText(dir / "runs.txt"));
    for (std::string line; std::getline(runs, line);) s.run_dirs.push_back(line);
    found.push_back(std::move(s));
  }
}

// The array's tasks as squeue shows them; nullopt when squeue could not say (logged).
std::optional<std::map<int, SlurmTaskState>> queueStates(const std::string& job_id) {
  const CommandOutput q =
      runCommand({"squeue", "-h", "-r", "-t", "all", "-j", job_id, "-o", "%i|%T"});
  if (q.succeeded()) return parseSlurmTaskStates(q.out, job_id);
  // squeue forgets a job some minutes after its end (MinJobAge): nothing of it runs.
  if (q.started && q.err.find("Invalid job id") != std::string::npos)
    return std::map<int, SlurmTaskState>{};
  std::cerr << "omnidso: squeue: " << q.describe() << "\n";
  return std::nullopt;
}

size_t countActive(const std::map<int, SlurmTaskState>& states) {
  size_t n = 0;
  for (const auto& [index, s] : states) n += isActiveSlurmState(s.state);
  return n;
}

// The final states of `indices` from sacct, asked until it knows all of them (the accounting
// database hears of a task's end a little after the controller) or `patience` has passed.
std::map<int, SlurmTaskState> accountedStates(const std::string& job_id,
                                              const std::vector<int>& indices, double patience_s,
                                              std::string& sacct_error) {
  const Clock::time_point start = Clock::now();
  std::map<int, SlurmTaskState> states;
  while (true) {
    const CommandOutput a = runCommand({"sacct", "-n", "-X", "-P", "-j", job_id, "-o",
                                        "JobID,State,ExitCode,Elapsed,NodeList,Reason"});
    if (!a.succeeded()) {
      sacct_error = a.describe();
      return {};
    }
    states = parseSlurmTaskStates(a.out, job_id);
    bool known = true;
    for (int i : indices) known = known && states.count(i) && !isActiveSlurmState(states[i].state);
    if (known || std::chrono::duration<double>(Clock::now() - start).count() > patience_s)
      return states;
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
}

// The array tasks of `s` whose run has no result.json (and is in the plan).
std::vector<int> unfinishedTasks(const Submission& s,
                                 const std::map<std::string, const PlannedRun*>& runs) {
  std::vector<int> unfinished;
  for (size_t i = 0; i < s.run_dirs.size(); ++i)
    if (!fs::exists(fs::path(s.run_dirs[i]) / "result.json") && runs.count(s.run_dirs[i]))
      unfinished.push_back(static_cast<int>(i));
  return unfinished;
}

// cluster.json for the `unfinished` tasks of `s`, which have ended.
void recordFailures(const Submission& s, const std::vector<int>& unfinished,
                    const std::map<std::string, const PlannedRun*>& runs,
                    const std::map<int, SlurmTaskState>& last_queue_states, const SlurmOptions& o) {
  if (unfinished.empty()) return;
  std::string sacct_error;
  const double patience_s = std::max(30.0, 2 * o.poll_interval_s);
  std::map<int, SlurmTaskState> states =
      accountedStates(s.job_id, unfinished, patience_s, sacct_error);
  for (int i : unfinished) {
    // A task that completed wrote its result.json; a shared file system may show it late.
    if (states.count(i) && states[i].state == "COMPLETED")
      for (int wait = 0; wait < 10 && !fs::exists(fs::path(s.run_dirs[i]) / "result.json"); ++wait)
        std::this_thread::sleep_for(std::chrono::seconds(1));
    const std::string output = (s.dir / fmt::format("task-{}.out", i)).string();
    std::string reason;
    if (states.count(i)) {
      reason = slurmFailureReason(s.job_id, i, states[i], output);
    } else if (last_queue_states.count(i)) {
      reason = slurmFailureReason(s.job_id, i, last_queue_states.at(i), output) +
               " [squeue; sacct: " + (sacct_error.empty() ? "no record" : sacct_error) + "]";
    } else {
      reason = fmt::format("Slurm: no record of job {}_{} (sacct: {}); see {}", s.job_id, i,
                           sacct_error.empty() ? "no record" : sacct_error, output);
    }
    writeClusterFailure(*runs.at(s.run_dirs[i]), reason);
  }
}

std::map<std::string, const PlannedRun*> runsByDirectory(const AblationPlan& plan) {
  std::map<std::string, const PlannedRun*> runs;
  for (const PlannedRun& r : plan.runs) runs[r.directory] = &r;
  return runs;
}

class SlurmExecutor : public AblationExecutor {
 public:
  explicit SlurmExecutor(SlurmOptions options) : o_(std::move(options)) {}

  bool execute(const ExecutionRequest& request) override {
    if (request.pending.empty()) return true;
    const std::vector<Submission> earlier = submissions(request.out_dir);
    for (const Submission& s : earlier)
      if (!s.job_id.empty()) {
        const auto states = queueStates(s.job_id);
        if (!states || countActive(*states))
          throw Error(fmt::format(
              "Slurm job {} (submitted earlier from {}) still has tasks queued or running; "
              "wait for it, or cancel it (scancel {}), before submitting again",
              s.job_id, s.dir.string(), s.job_id));
      }
    Submission s{
        fs::path(request.out_dir) / "slurm" / ("submission-" + std::to_string(earlier.size() + 1)),
        {},
        {}};
    const std::string script = writeSubmission(request, s);
    if (o_.dry_run) {
      std::cerr << fmt::format("wrote {} ({} array tasks); submit it with: sbatch {}\n", script,
                               s.run_dirs.size(), script);
      return false;
    }
    const CommandOutput submitted = runCommand({"sbatch", "--parsable", script});
    if (!submitted.succeeded()) throw Error("sbatch " + script + ": " + submitted.describe());
    s.job_id = submitted.out.substr(0, submitted.out.find_first_of(";\n"));
    std::ofstream(s.dir / "job_id") << s.job_id << "\n";
    std::cerr << fmt::format("submitted Slurm job array {} ({} tasks, script {})\n", s.job_id,
                             s.run_dirs.size(), script);
    if (!o_.wait) {
      std::cerr << fmt::format(
          "not waiting; follow it with `squeue -j {}`, build the tables "
          "with `omnidso ablate --collect --out {}`\n",
          s.job_id, request.out_dir);
      return false;
    }
    follow(request, s);
    return true;
  }

 private:
  // planned.json per run, job.sh and runs.txt; returns the script's path.
  std::string writeSubmission(const ExecutionRequest& request, Submission& s) const {
    fs::create_directories(s.dir);
    std::vector<std::vector<std::string>> tasks;
    std::ofstream runs(s.dir / "runs.txt");
    for (size_t i : request.pending) {
      const PlannedRun& run = request.plan->runs[i];
      writePlannedRun(run);
      fs::remove(fs::path(run.directory) / kClusterFailureFile);  // queued again: not failed
      tasks.push_back(taskArguments(run, request.executable, request.timeout_s));
      s.run_dirs.push_back(run.directory);
      runs << run.directory << "\n";
    }
    const fs::path script = s.dir / "job.sh";
    std::ofstream(script) << slurmArrayScript(tasks, o_.resources,
                                              o_.limit_running ? request.jobs : 0, s.dir.string());
    fs::permissions(script, fs::perms::owner_exec, fs::perm_options::add);
    return script.string();
  }

  // Prints each run as its result.json appears and polls squeue until no task is active.
  void follow(const ExecutionRequest& request, const Submission& s) const {
    const AblationPlan& plan = *request.plan;
    std::vector<size_t> unreported = request.pending;
    RunProgress progress(unreported.size(), request.quiet);
    std::map<int, SlurmTaskState> last_states;
    Clock::time_point last_poll = Clock::now() - std::chrono::hours(1);
    while (true) {
      reportEndedRuns(plan, unreported, false, progress);
      if (std::chrono::duration<double>(Clock::now() - last_poll).count() >= o_.poll_interval_s) {
        last_poll = Clock::now();
        if (const auto states = queueStates(s.job_id)) {
          for (const auto& [i, state] : *states) last_states[i] = state;
          size_t pending = 0, running = 0;
          for (const auto& [i, state] : *states) {
            if (state.state == "PENDING")
              ++pending;
            else if (isActiveSlurmState(state.state))
              ++running;
          }
          progress.redraw(fmt::format("job {}: queued {}, running {}, failed {}", s.job_id, pending,
                                      running, progress.failed()));
          if (pending + running == 0) break;
        }
      }
      std::this_thread::sleep_for(
          std::chrono::milliseconds(static_cast<int>(std::min(1.0, o_.poll_interval_s) * 1000)));
    }
    const auto runs = runsByDirectory(plan);
    recordFailures(s, unfinishedTasks(s, runs), runs, last_states, o_);
    reportEndedRuns(plan, unreported, true, progress);
  }

  SlurmOptions o_;
};

}  // namespace

std::unique_ptr<AblationExecutor> makeSlurmExecutor(const SlurmOptions& options) {
  return std::make_unique<SlurmExecutor>(options);
}

void recordSlurmFailures(const std::string& out_dir, const AblationPlan& plan,
                         const SlurmOptions& options) {
  const std::vector<Submission> all = submissions(out_dir);
  const auto runs = runsByDirectory(plan);
  std::set<std::string> seen;  // a run's cluster.json belongs to its latest submission
  for (auto s = all.rbegin(); s != all.rend(); ++s) {
    std::vector<int> needed;
    for (int i : unfinishedTasks(*s, runs))
      if (seen.insert(s->run_dirs[i]).second &&
          !fs::exists(fs::path(s->run_dirs[i]) / kClusterFailureFile))
        needed.push_back(i);
    if (needed.empty() || s->job_id.empty()) continue;
    const auto states = queueStates(s->job_id);
    if (!states || countActive(*states)) continue;  // still running: its runs are missing
    recordFailures(*s, needed, runs, *states, options);
  }
}

}  // namespace omnidso::cli
