// `omnidso eval`: ATE and RPE of an estimated trajectory against ground truth. The metrics
// and their definitions live in omnidso/core/metrics.hpp; this file only parses options
// and prints a table or JSON.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <omnidso/cli/commands.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <omnidso/core/scale_drift.hpp>
#include <omnidso/cli/scale_drift_json.hpp>
#include <omnidso/cli/eval_plot.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {
namespace {

struct EvalArguments {
  std::string gt_path;
  std::string est_path;
  std::string format = "tum";
  std::string gt_format;  // empty: same as --format
  std::string align = "sim3";
  double max_dt = 0.02;
  double delta = 1.0;
  std::string delta_unit = "f";
  bool pairs_from_reference = false;
  bool json = false;
  double drift_window_m = 0.0;  // 0: computeScaleDriftDefaultWindow
  std::string plot;             // PNG: ATE and local scale over time
  bool strict = false;  // refuse repeated or out-of-order timestamps instead of repairing
  std::string kitti_times;  // KITTI's times.txt: stamps the KITTI-format file's poses
};

// A KITTI file's poses stamped by line (trajectory_io.hpp: pose k at time k), given the times
// (dataset.hpp, readKittiTimes).
void stampKittiPoses(Trajectory* poses, const std::vector<KittiTimestamp>& times,
                     const std::string& poses_path, const std::string& times_path) {
  if (poses->size() != times.size())
    throw fileError(poses_path, fmt::format("{} poses, but {} lists {} timestamps", poses->size(),
                                            times_path, times.size()));
  for (std::size_t k = 0; k < times.size(); ++k) (*poses)[k].timestamp = times[k].seconds;
}

nlohmann::ordered_json statisticsJson(const ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"count", s.count}};
}

nlohmann::ordered_json optionalStatisticsJson(const std::optional<ErrorStatistics>& s) {
  return s ? statisticsJson(*s) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json resultJson(const EvalArguments& args, const EvaluationResult& r,
                                  const std::optional<ScaleDrift>& drift, size_t gt_poses,
                                  size_t est_poses) {
  const Eigen::Matrix3d rotation = r.alignment.rotationMatrix();
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({rotation(i, 0), rotation(i, 1), rotation(i, 2)});
  const Eigen::Vector3d& t = r.alignment.translation();
  return {{"ate", statisticsJson(r.ate)},
          {"rpe",
           {{"delta", args.delta},
            {"delta_unit", args.delta_unit},
            {"translation_m", optionalStatisticsJson(r.rpe_translation_m)},
            {"rotation_deg", optionalStatisticsJson(r.rpe_rotation_deg)}}},
          {"alignment",
           {{"type", args.align},
            {"scale", r.alignment.scale()},
            {"rotation", rows},
            {"translation", {t.x(), t.y(), t.z()}}}},
          {"matched_poses", r.association.size()},
          {"gt_poses", gt_poses},
          {"est_poses", est_poses},
          {"gt_length_m", r.gt_length_m},
          {"scale_drift", drift ? nlohmann::ordered_json(scaleDriftJson(*drift, true))
                                : nlohmann::ordered_json(nullptr)}};
}

std::string statisticsRow(const std::string& label, const std::optional<ErrorStatistics>& s) {
  if (!s) return fmt::format("{:<12}{:>12}\n", label, "n/a (too short for one pair)");
  return fmt::format("{:<12}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}{:>12.6f}\n", label,
                     s->rmse, s->mean, s->median, s->std, s->min, s->max);
}

void printTable(const EvalArguments& args, const EvaluationResult& r,
                const std::optional<ScaleDrift>& drift, size_t gt_poses, size_t est_poses) {
  std::cout << fmt::format("matched poses  {} (ground truth {}, estimate {})\n",
                           r.association.size(), gt_poses, est_poses)
            << fmt::format("alignment      {} (scale {:.6f})\n", args.align, r.alignment.scale())
            << fmt::format("gt length      {:.3f} m\n", r.gt_length_m)
            << fmt::format("RPE delta      {} {}\n\n", args.delta, args.delta_unit)
            << fmt::format("{:<12}{:>12}{:>12}{:>12}{:>12}{:>12}{:>12}\n", "", "rmse", "mean",
                           "median", "std", "min", "max")
            << statisticsRow("ATE (m)", r.ate) << statisticsRow("RPE (m)", r.rpe_translation_m)
            << statisticsRow("RPE (deg)", r.rpe_rotation_deg);
  if (!drift) {
    std::cout << "\nscale drift    n/a (too short for three windows)\n";
    return;
  }
  std::cout << fmt::format("\nscale drift    window {:.3f} m, {} samples: {:+.3f} % over the "
                           "sequence, {:+.3f} % per 10 m, {:+.3f} % per minute; local scale "
                           "{:.4f} … {:.4f}\n",
                           drift->window_m, drift->samples.size(), drift->percent_over_sequence,
                           drift->percent_per_10m, drift->percent_per_minute, drift->min_ratio,
                           drift->max_ratio);
}

// The reader's repairs (repeated timestamps dropped, lines sorted) go to stderr, so that
// stdout stays the table or JSON a script parses.
Trajectory readReportingWarnings(const std::string& path, TrajectoryFormat format, bool strict) {
  TrajectoryFile file = readTrajectoryFile(
      path, format, strict ? TimestampPolicy::kStrict : TimestampPolicy::kTolerant);
  for (const std::string& warning : file.warnings) std::cerr << "warning: " << warning << "\n";
  return std::move(file.poses);
}

void runEval(const EvalArguments& args) {
  const TrajectoryFormat est_format = parseTrajectoryFormat(args.format);
  const TrajectoryFormat gt_format =
      parseTrajectoryFormat(args.gt_format.empty() ? args.format : args.gt_format);
  Trajectory gt = readReportingWarnings(args.gt_path, gt_format, args.strict);
  Trajectory est = readReportingWarnings(args.est_path, est_format, args.strict);

  EvaluationOptions options;
  options.alignment = parseAlignmentType(args.align);
  options.max_dt = args.max_dt;
  // KITTI files carry no timestamps: with KITTI's times.txt their poses are stamped and
  // matched by time; without it poses correspond by line, which only holds when both files
  // list the same frames (an estimate of keyframes only would be paired with the wrong poses).
  const bool gt_kitti = gt_format == TrajectoryFormat::kKitti;
  const bool est_kitti = est_format == TrajectoryFormat::kKitti;
  if (!args.kitti_times.empty()) {
    if (!gt_kitti && !est_kitti)
      throw Error("--kitti-times stamps a KITTI-format file, but neither --format nor "
                  "--gt-format is kitti");
    const std::vector<KittiTimestamp> times = readKittiTimes(args.kitti_times);
    if (gt_kitti) stampKittiPoses(&gt, times, args.gt_path, args.kitti_times);
    if (est_kitti) stampKittiPoses(&est, times, args.est_path, args.kitti_times);
  } else if ((gt_kitti || est_kitti) && gt.size() != est.size()) {
    throw fileError(gt_kitti ? args.gt_path : args.est_path,
                    fmt::format("KITTI poses carry no timestamps and pair by line, but the ground "
                                "truth holds {} poses and the estimate {}: pass KITTI's times.txt "
                                "with --kitti-times to match them by time",
                                gt.size(), est.size()));
  }
  options.associate_by_index = (gt_kitti || est_kitti) && args.kitti_times.empty();
  options.rpe.delta = args.delta;
  options.rpe.unit = parseDeltaUnit(args.delta_unit);
  options.rpe.pairs_from_reference = args.pairs_from_reference;

  EvaluationResult result;
  try {
    result = evaluate(gt, est, options);
  } catch (const Error& e) {
    // Name both files: no overlap or too few matches concerns the pair.
    throw fileError(args.est_path, std::string(e.what()) + fmt::format(
        " (ground truth {}: {} poses in [{:.6f}, {:.6f}] s; estimate: {} poses in "
        "[{:.6f}, {:.6f}] s)", args.gt_path, gt.size(), gt.front().timestamp,
        gt.back().timestamp, est.size(), est.front().timestamp, est.back().timestamp));
  }
  const std::optional<ScaleDrift> drift =
      args.drift_window_m > 0 ? computeScaleDrift(gt, est, result, args.drift_window_m)
                              : computeScaleDriftDefaultWindow(gt, est, result);
  if (!args.plot.empty()) writeEvaluationPlot(args.plot, gt, result, drift);
  if (args.json) {
    std::cout << resultJson(args, result, drift, gt.size(), est.size()).dump(2) << "\n";
  } else {
    printTable(args, result, drift, gt.size(), est.size());
  }
}

}  // namespace

void registerEvalCommand(CLI::App& app) {
  auto args = std::make_shared<EvalArguments>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "ATE and RPE of an estimated trajectory against ground truth (evo conventions)");
  const auto formats = CLI::IsMember({"tum", "kitti", "euroc"});
  cmd->add_option("--gt", args->gt_path, "ground-truth trajectory file")->required();
  cmd->add_option("--est", args->est_path, "estimated trajectory file")->required();
  cmd->add_option("--format", args->format, "file format of --est (and of --gt by default)")
      ->check(formats)
      ->capture_default_str();
  cmd->add_option("--gt-format", args->gt_format, "file format of --gt if it differs")
      ->check(formats);
  cmd->add_option("--align", args->align, "alignment of the estimate to the ground truth")
      ->check(CLI::IsMember({"sim3", "se3", "posyaw", "none"}))
      ->capture_default_str();
  cmd->add_option("--max-dt", args->max_dt, "max. timestamp difference for association (s)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--delta", args->delta, "RPE delta (frames or metres)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--delta-unit", args->delta_unit, "RPE delta unit: f (frames) or m (metres)")
      ->check(CLI::IsMember({"f", "m"}))
      ->capture_default_str();
  cmd->add_flag("--pairs-from-reference", args->pairs_from_reference,
                "RPE in metres: choose pairs along the ground truth, not the estimate");
  cmd->add_option("--drift-window", args->drift_window_m,
                  "scale drift: ground-truth path length over which the local scale is "
                  "measured (m; default a tenth of the path, at least 0.5 m, halved while fewer "
                  "than half the pairs give a chord of at least half of it)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--plot", args->plot,
                  "write a PNG: ATE over time beside the local scale over time (refused if it exists)");
  cmd->add_option("--kitti-times", args->kitti_times,
                  "KITTI's times.txt (one timestamp per line): stamps the poses of the file in "
                  "kitti format, which are then matched by time (without it they pair by line, "
                  "and both files must list the same frames)");
  cmd->add_flag("--json", args->json, "print a JSON object instead of a table");
  cmd->add_flag("--strict", args->strict,
                "refuse repeated or out-of-order timestamps (default: keep the first of "
                "repeated ones and sort, with a warning)");
  cmd->callback([args] { runEval(*args); });
}

}  // namespace omnidso::cli
