// `omnidso ablate`: the paper's ablation (Matsuki et al. 2018, Tables I–V) as a grid of
// `omnidso run` processes — datasets × camera models × N_f, `--runs` seeds each, `--jobs` at
// a time — then medians, tables and plots. The grid is ablation_plan.cc, who performs the runs
// the executors (ablation_executor.hpp: this machine, a Slurm job array, GNU parallel), a
// run's success ablation_run_result.cc, the tables ablation_tables.cc and ablation_report.cc,
// the plots ablation_plots.cc. `--collect` builds the tables from the result.json files in
// --out alone, with the grid recorded in its ablation.json (ablation_manifest.cc).
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <omnidso/cli/ablation_executor.hpp>
#include <omnidso/cli/ablation_manifest.hpp>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/ablation_plots.hpp>
#include <omnidso/cli/ablation_report.hpp>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/ablation_tables.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/cli/parallel_executor.hpp>
#include <omnidso/cli/shell_words.hpp>
#include <omnidso/cli/slurm_executor.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <omnidso/synth/dataset_loading.hpp>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

struct AblateArguments {
  std::string datasets;
  std::string camera_models = "native";
  std::string keyframes = "7,5,3";
  int runs = 5;
  int jobs = 1;
  double timeout_s = 3600;
  std::uint64_t seed = 0;
  std::string out;
  RunPassThrough pass_through;
  std::string executable;
  bool quiet = false;
  std::string executor = "local";
  bool collect = false;
  bool no_wait = false;
  bool dry_run = false;
  bool jobs_given = false;  // Slurm's %M only when --jobs was asked for
  SlurmOptions slurm;
  std::string parallel_arguments;
};

// A dataset's ground truth over the frames the runs use, and Table II's facts.
struct DatasetTruth {
  DatasetFacts facts;
  Trajectory ground_truth;
  double max_dt = 0.02;
};

DatasetTruth readDatasetTruth(const AblationCell& cell, int max_frames) {
  const DatasetIndex index = openDataset(cell.dataset_path);
  if (!index.groundtruth_path)
    throw Error(cell.dataset_path +
                ": the dataset has no ground truth, which the ablation's "
                "ATE needs");
  if (index.frames.empty()) throw Error(cell.dataset_path + ": the dataset has no frames");
  const size_t used =
      max_frames > 0 ? std::min(index.frames.size(), size_t(max_frames)) : index.frames.size();
  const double t0 = index.frames.front().timestamp_s, t1 = index.frames[used - 1].timestamp_s;
  DatasetTruth truth;
  const double rate = datasetFrameRate(index);
  truth.max_dt = rate > 0 ? 0.5 / rate : 0.02;
  for (const StampedPose& p : synth::cameraGroundTruth(index))
    if (p.timestamp >= t0 - truth.max_dt && p.timestamp <= t1 + truth.max_dt)
      truth.ground_truth.push_back(p);
  truth.facts = {cell.dataset_name, used, t1 - t0, pathLength(truth.ground_truth, t0, t1)};
  return truth;
}

std::string executablePath(const std::string& requested) {
  const std::string path =
      requested.empty() ? fs::read_symlink("/proc/self/exe").string() : requested;
  if (::access(path.c_str(), X_OK) != 0)
    throw Error("--omnidso: " + path + " is not an executable file");
  return path;
}

template <typename T>
std::string joined(const std::vector<T>& items) {
  std::string text;
  for (const T& item : items) text += fmt::format("{}{}", text.empty() ? "" : ",", item);
  return text;
}

std::string preamble(const AblationManifest& m) {
  const AblationSpec& spec = m.spec;
  const RunPassThrough& p = spec.pass_through;
  return fmt::format(
      "Camera models `{}`, N_f `{}` (reference N_f = {}), {} runs per cell with seeds {}…{}. "
      "Every run: `--points {}`, `--threads {}`, `--residuals {}`, {}, {}; timeout {}.",
      joined(spec.camera_models), joined(spec.keyframes), spec.keyframes.front(), spec.runs,
      spec.base_seed, spec.base_seed + spec.runs - 1, p.points, p.threads, p.residuals,
      p.max_frames > 0 ? fmt::format("the first {} frames", p.max_frames) : "all frames",
      p.no_intrinsics_opt ? "intrinsics fixed" : "intrinsics optimised",
      m.timeout_s > 0 ? fmt::format("{:g} s", m.timeout_s) : "none");
}

DatasetPlots plotInput(const DatasetTruth& truth, const std::vector<CellSummary>& cells,
                       const AblationPlan& plan, int runs) {
  DatasetPlots plots{truth.facts.name, truth.ground_truth, truth.max_dt, {}};
  for (size_t c = 0; c < cells.size(); ++c) {
    const CellSummary& cell = cells[c];
    if (cell.cell.dataset_name != truth.facts.name) continue;
    const size_t failed = cell.runs.size() - cell.succeeded - cell.missing;
    std::string failures = failed ? fmt::format("failed {}/{}", failed, cell.runs.size()) : "";
    if (cell.missing)
      failures +=
          fmt::format("{}missing {}/{}", failed ? ", " : "", cell.missing, cell.runs.size());
    if (!cell.median_run) {
      plots.methods.push_back({cell.cell.method() + ": " + failures, std::nullopt});
      continue;
    }
    const RunResult& r = cell.runs[*cell.median_run];
    const PlannedRun& run = plan.runs[c * runs + (r.run - 1)];
    PlottedMethod method{
        fmt::format("{} (run {}, RMSE {:.4f} m{})", cell.cell.method(), r.run,
                    r.rmse_m.value_or(0.0), failures.empty() ? "" : "; " + failures),
        std::nullopt};
    try {
      method.keyframes = readTrajectoryTum((fs::path(run.directory) / "keyframes.txt").string());
    } catch (const Error& e) {
      method.label += std::string(": ") + e.what();
    }
    plots.methods.push_back(std::move(method));
  }
  return plots;
}

// The grid asked for on the command line; bad settings are refused here, not by every run.
AblationManifest requestedGrid(const AblateArguments& args) {
  if (args.datasets.empty()) throw Error("--datasets is required (unless --collect)");
  AblationManifest m;
  AblationSpec& spec = m.spec;
  spec.datasets = splitList(args.datasets, "--datasets");
  spec.camera_models = splitList(args.camera_models, "--camera-models");
  spec.keyframes = parseIntegerList(args.keyframes, "--keyframes");
  spec.runs = args.runs;
  spec.base_seed = args.seed;
  spec.pass_through = args.pass_through;
  OdometryOptions check;
  if (!spec.pass_through.config.empty()) {
    applyOdometryConfigFile(check, spec.pass_through.config);
    spec.pass_through.config = fs::absolute(spec.pass_through.config).string();  // for every run
  }
  for (const std::string& setting : spec.pass_through.settings)
    applyOdometrySettingAssignment(check, setting);
  m.timeout_s = args.timeout_s;
  m.jobs = args.jobs;
  return m;
}

std::unique_ptr<AblationExecutor> makeExecutor(const AblateArguments& args,
                                               const AblationSpec& spec) {
  if (args.executor == "slurm") {
    SlurmOptions o = args.slurm;
    o.wait = !args.no_wait;
    o.dry_run = args.dry_run;
    o.limit_running = args.jobs_given;
    if (o.resources.cpus == 0) o.resources.cpus = spec.pass_through.threads;
    return makeSlurmExecutor(o);
  }
  if (args.no_wait) throw Error("--no-wait: only with --executor slurm");
  if (args.executor == "parallel") {
    ParallelOptions o;
    o.arguments = splitShellWords(args.parallel_arguments, "--parallel-args");
    o.dry_run = args.dry_run;
    return makeParallelExecutor(o);
  }
  if (args.dry_run) throw Error("--dry-run: only with --executor slurm or parallel");
  return makeLocalExecutor();
}

// Performs the runs without a result.json; false when they were handed over and not waited for.
bool performPendingRuns(const AblateArguments& args, const AblationManifest& manifest,
                        const AblationPlan& plan, const std::string& out) {
  std::unique_ptr<AblationExecutor> executor = makeExecutor(args, manifest.spec);
  ExecutionRequest request{
      &plan, {}, executablePath(args.executable), out, args.timeout_s, args.jobs, args.quiet};
  prepareAblationDirectory(out);
  for (size_t i = 0; i < plan.runs.size(); ++i)
    if (!readFinishedRun(plan.runs[i])) request.pending.push_back(i);  // throws: other settings
  writeAblationManifest(out, plan, manifest);
  std::cerr << fmt::format(
      "{} cells × {} runs = {} runs: {} finished earlier in {} (not run again), {} to run, "
      "executor {}\n",
      plan.cells.size(), manifest.spec.runs, plan.runs.size(),
      plan.runs.size() - request.pending.size(), out, request.pending.size(), args.executor);
  return executor->execute(request);
}

void runAblate(const AblateArguments& args) {
  const std::string out = fs::absolute(args.out).lexically_normal().string();
  if (args.collect && !args.datasets.empty())
    throw Error("--collect takes the grid from " + out + "/" + kAblationMarker +
                "; leave out --datasets");
  const AblationManifest manifest = args.collect ? readAblationManifest(out) : requestedGrid(args);
  const AblationSpec& spec = manifest.spec;
  const AblationPlan plan = planAblation(spec, out);
  std::vector<DatasetTruth> truths;  // cells are dataset-major: one per dataset
  for (size_t c = 0; c < plan.cells.size(); c += spec.camera_models.size() * spec.keyframes.size())
    truths.push_back(readDatasetTruth(plan.cells[c], spec.pass_through.max_frames));
  if (args.collect) {
    recordSlurmFailures(out, plan, args.slurm);  // of jobs submitted with --no-wait
  } else if (!performPendingRuns(args, manifest, plan, out)) {
    return;
  }

  std::vector<CellSummary> cells;
  size_t failed = 0, missing = 0;
  for (size_t c = 0; c < plan.cells.size(); ++c) {
    std::vector<RunResult> runs;
    for (int k = 0; k < spec.runs; ++k)
      runs.push_back(currentRunState(plan.runs[c * spec.runs + k]));
    cells.push_back(summarizeCell(plan.cells[c], std::move(runs)));
    missing += cells.back().missing;
    failed += cells.back().runs.size() - cells.back().succeeded - cells.back().missing;
  }
  std::vector<DatasetFacts> facts;
  for (const DatasetTruth& t : truths) facts.push_back(t.facts);
  writeAblationReport(out, preamble(manifest), ablationTables(facts, cells), cells);
  std::vector<std::string> plot_paths;
  for (const DatasetTruth& t : truths)
    for (const std::string& p : writeDatasetPlots((fs::path(out) / "plots").string(),
                                                  plotInput(t, cells, plan, spec.runs)))
      plot_paths.push_back(p);

  std::cout << fmt::format("{} of {} runs failed", failed, plan.runs.size())
            << (missing ? fmt::format(", {} missing (not finished)", missing) : "") << "\n"
            << "tables: " << (fs::path(out) / "tables.md").string() << " (and CSV files)\n";
  for (const std::string& p : plot_paths) std::cout << "plot:   " << p << "\n";
  size_t listed = 0;  // the missing runs, so that a collect says what is still to come
  for (const CellSummary& c : cells)
    for (const RunResult& r : c.runs)
      if (r.missing && listed++ < 20)
        std::cout << fmt::format("missing: {} {} run {} (seed {}): runs/{}/run{}\n",
                                 c.cell.dataset_name, c.cell.method(), r.run, r.seed, c.cell.id(),
                                 r.run);
  if (listed > 20) std::cout << fmt::format("… and {} more missing runs (runs.csv)\n", listed - 20);
}

}  // namespace

void registerAblateCommand(CLI::App& app) {
  auto args = std::make_shared<AblateArguments>();
  CLI::App* cmd = app.add_subcommand(
      "ablate",
      "the paper's ablation: every dataset × camera model × N_f, several seeds, as "
      "separate `omnidso run` processes; medians, Tables I–V and plots (resumable)");
  cmd->add_option("--datasets", args->datasets,
                  "comma-separated dataset directories (required unless --collect)");
  cmd->add_option("--camera-models", args->camera_models,
                  "comma-separated: native, pinhole-crop:FOV_DEG")
      ->capture_default_str();
  cmd->add_option("--keyframes", args->keyframes,
                  "comma-separated N_f values; the first is the reference of Table IV")
      ->capture_default_str();
  cmd->add_option("--runs", args->runs, "runs (seeds) per cell; tables show the median")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  CLI::Option* jobs = cmd->add_option("--jobs", args->jobs,
                                      "runs at a time (slurm: the array's %M, only when given)")
                          ->check(CLI::Range(1, 1000))
                          ->capture_default_str();
  cmd->add_option("--timeout", args->timeout_s,
                  "seconds before a run is killed and failed (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "seed of run 1; run k uses seed + k - 1")
      ->capture_default_str();
  cmd->add_option("--out", args->out,
                  "output directory: new, empty, or an earlier ablation's (finished runs are kept)")
      ->required();
  RunPassThrough& p = args->pass_through;
  cmd->add_option("--points", p.points, "passed to every run")
      ->check(CLI::Range(10, 100000))
      ->capture_default_str();
  cmd->add_option("--max-frames", p.max_frames, "passed to every run (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-intrinsics-opt", p.no_intrinsics_opt, "passed to every run");
  cmd->add_flag("--no-vignette-estimation", p.no_vignette_estimation, "passed to every run");
  cmd->add_option("--threads", p.threads,
                  "passed to every run: 1 deterministic, N > 1 real-time mode with N Ceres threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--residuals", p.residuals, "passed to every run: analytic | autodiff")
      ->check(CLI::IsMember({"analytic", "autodiff"}))
      ->capture_default_str();
  cmd->add_option("--config", p.config, "odometry settings file passed to every run")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", p.settings,
                  "odometry setting NAME=VALUE passed to every run (repeatable)");
  cmd->add_option("--omnidso", args->executable,
                  "the omnidso executable that performs the runs (default: this one)");
  cmd->add_flag("--quiet", args->quiet, "no progress output");
  cmd->add_option("--executor", args->executor,
                  "who performs the runs: local (this machine, --jobs at a time), slurm (one "
                  "job array), parallel (GNU parallel)")
      ->check(CLI::IsMember({"local", "slurm", "parallel"}))
      ->capture_default_str();
  cmd->add_flag("--collect", args->collect,
                "run nothing: build the tables from the runs in --out that have finished "
                "(the grid is read from its ablation.json); missing runs are marked");
  cmd->add_flag("--dry-run", args->dry_run,
                "slurm, parallel: only write the job script / job list into --out");
  cmd->add_flag("--no-wait", args->no_wait,
                "slurm: return once the job array is submitted (then --collect)");
  SlurmResources& r = args->slurm.resources;
  r.cpus = 0;  // 0: --threads
  cmd->add_option("--slurm-partition", r.partition, "slurm: sbatch --partition");
  cmd->add_option("--slurm-time", r.time, "slurm: sbatch --time per run, e.g. 1:00:00");
  cmd->add_option("--slurm-cpus", r.cpus, "slurm: sbatch --cpus-per-task (default: --threads)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--slurm-mem", r.mem, "slurm: sbatch --mem per run, e.g. 4G");
  cmd->add_option("--slurm-arg", r.extra,
                  "slurm: a further sbatch option for the script, e.g. --account=vision "
                  "(repeatable)");
  cmd->add_option("--poll-interval", args->slurm.poll_interval_s,
                  "slurm: seconds between squeue polls while waiting")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  cmd->add_option("--parallel-args", args->parallel_arguments,
                  "parallel: options passed to GNU parallel, e.g. \"--sshloginfile hosts\"");
  cmd->callback([args, jobs] {
    args->jobs_given = jobs->count() > 0;
    runAblate(*args);
  });
}

}  // namespace omnidso::cli
