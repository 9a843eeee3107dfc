// `omnidso ablate`: the paper's ablation (Matsuki et al. 2018, Tables I–V) as a grid of
// `omnidso run` processes — datasets × camera models × N_f, `--runs` seeds each, `--jobs` at
// a time — then medians, tables and plots. The grid is ablation_plan.cc, the processes
// process_pool.cc, a run's success ablation_run_result.cc, the tables ablation_tables.cc and
// ablation_report.cc, the plots ablation_plots.cc.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/ablation_plots.hpp>
#include <omnidso/cli/ablation_report.hpp>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/ablation_tables.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/cli/odometry_settings.hpp>
#include <omnidso/cli/process_pool.hpp>
#include <omnidso/cli/progress.hpp>
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

std::string preamble(const AblationSpec& spec, const AblateArguments& args) {
  const RunPassThrough& p = spec.pass_through;
  return fmt::format(
      "Camera models `{}`, N_f `{}` (reference N_f = {}), {} runs per cell with seeds {}…{}. "
      "Every run: `--points {}`, `--threads {}`, `--residuals {}`, {}, {}; timeout {}.",
      args.camera_models, args.keyframes, spec.keyframes.front(), spec.runs, spec.base_seed,
      spec.base_seed + spec.runs - 1, p.points, p.threads, p.residuals,
      p.max_frames > 0 ? fmt::format("the first {} frames", p.max_frames) : "all frames",
      p.no_intrinsics_opt ? "intrinsics fixed" : "intrinsics optimised",
      args.timeout_s > 0 ? fmt::format("{:g} s", args.timeout_s) : "none");
}

void writeManifest(const std::string& out, const AblationPlan& plan, const AblationSpec& spec,
                   const AblateArguments& args) {
  nlohmann::json cells = nlohmann::json::array();
  for (const AblationCell& c : plan.cells)
    cells.push_back({{"id", c.id()},
                     {"dataset", c.dataset_name},
                     {"dataset_path", c.dataset_path},
                     {"camera_model", c.camera_model},
                     {"keyframes", c.keyframes}});
  const nlohmann::json manifest = {
      {"omnidso_ablation", 1},
      {"runs_per_cell", spec.runs},
      {"base_seed", spec.base_seed},
      {"timeout_s", args.timeout_s},
      {"jobs", args.jobs},
      {"cells", cells},
      {"note", "written by omnidso ablate; runs with a result.json are not run again"}};
  std::ofstream(fs::path(out) / kAblationMarker) << manifest.dump(2) << "\n";
}

std::string resultLine(const PlannedRun& run, const AblationCell& cell, const RunResult& r) {
  const std::string what =
      fmt::format("{} {} run {} (seed {})", cell.dataset_name, cell.method(), run.run, run.seed);
  if (!r.ok) return fmt::format("{}: FAILED, {} ({:.1f} s)", what, r.failure, r.wall_s);
  return fmt::format("{}: ok, RMSE {:.4f} m ({:.1f} s)", what, r.rmse_m.value_or(0.0), r.wall_s);
}

// Runs the unfinished runs, printing a line per finished run (and a bar on a terminal).
void runPending(const AblationPlan& plan, const std::vector<size_t>& pending,
                std::vector<std::optional<RunResult>>& results, const std::string& executable,
                const AblateArguments& args) {
  std::vector<ProcessSpec> specs;
  for (size_t i : pending) {
    const PlannedRun& run = plan.runs[i];
    fs::create_directories(run.directory);
    ProcessSpec spec{{executable}, (fs::path(run.directory) / "log.txt").string(), args.timeout_s};
    spec.argv.insert(spec.argv.end(), run.arguments.begin(), run.arguments.end());
    specs.push_back(std::move(spec));
  }
  const bool bar = !args.quiet && ::isatty(STDERR_FILENO);
  size_t done = 0, failed = 0, running = 0;
  auto drawBar = [&] {
    if (bar)
      printProgressBar(done, specs.size(), fmt::format("running {}, failed {}", running, failed));
  };
  ProcessCallbacks callbacks;
  callbacks.started = [&](size_t) { ++running, drawBar(); };
  callbacks.finished = [&](size_t k, const ProcessOutcome& outcome) {
    const PlannedRun& run = plan.runs[pending[k]];
    const RunResult r = classifyRun(run, outcome);
    writeRunResult(run.directory, r);
    results[pending[k]] = r;
    --running, ++done, failed += !r.ok;
    if (!args.quiet) {
      if (bar) std::fprintf(stderr, "\r\033[K");
      std::fprintf(stderr, "[%zu/%zu] %s\n", done, specs.size(),
                   resultLine(run, plan.cells[run.cell], r).c_str());
    }
    drawBar();
  };
  runProcesses(specs, args.jobs, callbacks);
}

DatasetPlots plotInput(const DatasetTruth& truth, const std::vector<CellSummary>& cells,
                       const AblationPlan& plan, int runs) {
  DatasetPlots plots{truth.facts.name, truth.ground_truth, truth.max_dt, {}};
  for (size_t c = 0; c < cells.size(); ++c) {
    const CellSummary& cell = cells[c];
    if (cell.cell.dataset_name != truth.facts.name) continue;
    const size_t failed = cell.runs.size() - cell.succeeded;
    const std::string failures =
        failed ? fmt::format("failed {}/{}", failed, cell.runs.size()) : "";
    if (!cell.median_run) {
      plots.methods.push_back({cell.cell.method() + ": " + failures, std::nullopt});
      continue;
    }
    const RunResult& r = cell.runs[*cell.median_run];
    const PlannedRun& run = plan.runs[c * runs + (r.run - 1)];
    PlottedMethod method{fmt::format("{} (run {}, RMSE {:.4f} m{})", cell.cell.method(), r.run,
                                     r.rmse_m.value_or(0.0), failed ? "; " + failures : ""),
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

void runAblate(const AblateArguments& args) {
  AblationSpec spec;
  spec.datasets = splitList(args.datasets, "--datasets");
  spec.camera_models = splitList(args.camera_models, "--camera-models");
  spec.keyframes = parseIntegerList(args.keyframes, "--keyframes");
  spec.runs = args.runs;
  spec.base_seed = args.seed;
  spec.pass_through = args.pass_through;
  {  // bad settings are refused here, not by every run; the runs get an absolute path
    OdometryOptions check;
    if (!spec.pass_through.config.empty()) {
      applyOdometryConfigFile(check, spec.pass_through.config);
      spec.pass_through.config = std::filesystem::absolute(spec.pass_through.config).string();
    }
    for (const std::string& setting : spec.pass_through.settings)
      applyOdometrySettingAssignment(check, setting);
  }
  const AblationPlan plan = planAblation(spec, args.out);
  std::vector<DatasetTruth> truths;  // cells are dataset-major: one per dataset
  for (size_t c = 0; c < plan.cells.size(); c += spec.camera_models.size() * spec.keyframes.size())
    truths.push_back(readDatasetTruth(plan.cells[c], spec.pass_through.max_frames));
  const std::string executable = executablePath(args.executable);
  prepareAblationDirectory(args.out);
  std::vector<std::optional<RunResult>> results(plan.runs.size());
  std::vector<size_t> pending;
  for (size_t i = 0; i < plan.runs.size(); ++i) {
    results[i] = readFinishedRun(plan.runs[i]);  // throws when made with other settings
    if (!results[i]) pending.push_back(i);
  }
  writeManifest(args.out, plan, spec, args);
  std::cerr << fmt::format(
      "{} cells × {} runs = {} runs: {} finished earlier in {} (not run "
      "again), {} to run, {} at a time\n",
      plan.cells.size(), spec.runs, plan.runs.size(), plan.runs.size() - pending.size(), args.out,
      pending.size(), args.jobs);
  runPending(plan, pending, results, executable, args);

  std::vector<CellSummary> cells;
  size_t failed = 0;
  for (size_t c = 0; c < plan.cells.size(); ++c) {
    std::vector<RunResult> runs;
    for (int k = 0; k < spec.runs; ++k) runs.push_back(*results[c * spec.runs + k]);
    cells.push_back(summarizeCell(plan.cells[c], std::move(runs)));
    failed += cells.back().runs.size() - cells.back().succeeded;
  }
  std::vector<DatasetFacts> facts;
  for (const DatasetTruth& t : truths) facts.push_back(t.facts);
  writeAblationReport(args.out, preamble(spec, args), ablationTables(facts, cells), cells);
  std::vector<std::string> plot_paths;
  for (const DatasetTruth& t : truths)
    for (const std::string& p : writeDatasetPlots((fs::path(args.out) / "plots").string(),
                                                  plotInput(t, cells, plan, spec.runs)))
      plot_paths.push_back(p);

  std::cout << fmt::format("{} of {} runs failed\n", failed, plan.runs.size())
            << "tables: " << (fs::path(args.out) / "tables.md").string() << " (and CSV files)\n";
  for (const std::string& p : plot_paths) std::cout << "plot:   " << p << "\n";
}

}  // namespace

void registerAblateCommand(CLI::App& app) {
  auto args = std::make_shared<AblateArguments>();
  CLI::App* cmd = app.add_subcommand(
      "ablate",
      "the paper's ablation: every dataset × camera model × N_f, several seeds, as "
      "separate `omnidso run` processes; medians, Tables I–V and plots (resumable)");
  cmd->add_option("--datasets", args->datasets, "comma-separated dataset directories")->required();
  cmd->add_option("--camera-models", args->camera_models,
                  "comma-separated: native, pinhole-crop:FOV_DEG")
      ->capture_default_str();
  cmd->add_option("--keyframes", args->keyframes,
                  "comma-separated N_f values; the first is the reference of Table IV")
      ->capture_default_str();
  cmd->add_option("--runs", args->runs, "runs (seeds) per cell; tables show the median")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--jobs", args->jobs, "runs in parallel")
      ->check(CLI::Range(1, 256))
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
  cmd->add_option("--threads", p.threads,
                  "passed to every run: 1 deterministic, N > 1 real-time mode with N Ceres threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--residuals", p.residuals, "passed to every run: analytic | autodiff")
      ->check(CLI::IsMember({"analytic", "autodiff"}))
      ->capture_default_str();
  cmd->add_option("--config", p.config, "odometry settings file passed to every run")
      ->check(CLI::ExistingFile);
  cmd->add_option("--set", p.settings, "odometry setting NAME=VALUE passed to every run (repeatable)");
  cmd->add_option("--omnidso", args->executable,
                  "the omnidso executable that performs the runs (default: this one)");
  cmd->add_flag("--quiet", args->quiet, "no progress output");
  cmd->callback([args] { runAblate(*args); });
}

}  // namespace omnidso::cli
