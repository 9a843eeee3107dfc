#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <omnidso/cli/ablation_report.hpp>
#include <omnidso/core/error.hpp>
#include <sstream>

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

std::string plain(const std::optional<double>& v) { return v ? fmt::format("{:.9g}", *v) : ""; }

// Written next to the final file and renamed, so that a reader never sees half a file.
void writeFile(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary);
    out << text;
    if (!out) throw Error(temporary.string() + ": cannot write");
  }
  fs::rename(temporary, path);
}

}  // namespace

std::string runStatus(const RunResult& r) { return r.ok ? "ok" : r.missing ? "missing" : "failed"; }

TextTable runsTable(const std::vector<CellSummary>& cells, bool failed_only) {
  TextTable t;
  t.header = {"dataset",
              "camera_model",
              "keyframes",
              "run",
              "seed",
              "status",
              "failure",
              "rmse_m",
              "rmse_percent_of_path",
              "tracking_ms_per_frame",
              "mapping_ms_per_keyframe",
              "wall_s",
              "log"};
  for (const CellSummary& c : cells)
    for (const RunResult& r : c.runs) {
      if (failed_only && runStatus(r) != "failed") continue;
      t.rows.push_back({c.cell.dataset_name, c.cell.camera_model, std::to_string(c.cell.keyframes),
                        std::to_string(r.run), std::to_string(r.seed), runStatus(r), r.failure,
                        plain(r.rmse_m), plain(r.rmse_percent_of_path), plain(r.tracking_ms),
                        plain(r.mapping_ms), fmt::format("{:.1f}", r.wall_s),
                        fmt::format("runs/{}/run{}/log.txt", c.cell.id(), r.run)});
    }
  return t;
}

std::string failureRuleText(int runs_per_cell) {
  return fmt::format(
      "Every cell was run {} times, run k with seed `--seed` + k − 1. Each value is the "
      "**median over the successful runs** of its cell. A run **fails** when its process "
      "exits non-zero, crashes or exceeds `--timeout`, when it does not initialise (no "
      "keyframe ATE), or when it loses tracking (a \"tracking lost\" event or more than one "
      "trajectory segment). `(failed k/n)` after a value: k of the n runs failed and the "
      "median is over the other n − k. `failed n/n`: no run succeeded, there is no value. "
      "Failed runs are listed with their reasons at the end and in `runs.csv`; a run the "
      "cluster ended (time limit, preemption, node failure, out of memory, cancelled) is "
      "failed with the cluster's reason, and run again by a resubmission. `(missing m/n)`: "
      "m runs have not finished (tables collected with `--collect` before the end).",
      runs_per_cell);
}

void writeAblationReport(const std::string& out_dir, const std::string& preamble,
                         const std::vector<AblationTable>& tables,
                         const std::vector<CellSummary>& cells) {
  const fs::path out(out_dir);
  std::ostringstream md;
  md << "# Ablation\n\n"
     << preamble << "\n\n"
     << failureRuleText(cells.empty() ? 0 : static_cast<int>(cells.front().runs.size())) << "\n";
  for (const AblationTable& t : tables) {
    md << "\n## " << t.title << "\n\n"
       << t.note << " (`" << t.csv_name << "`)\n\n"
       << markdownTable(t.markdown);
    writeFile(out / t.csv_name, csvTable(t.csv));
  }
  const TextTable failed = runsTable(cells, true);
  md << "\n## Failed runs\n\n";
  if (failed.rows.empty()) {
    md << "None. Every run is listed in `runs.csv`.\n";
  } else {
    md << failed.rows.size() << " failed runs; every run is listed in `runs.csv`.\n\n";
    TextTable brief;
    brief.header = {"dataset", "camera model", "N_f", "run", "seed", "reason", "log"};
    brief.label_columns = brief.header.size();
    for (const auto& row : failed.rows)
      brief.rows.push_back({row[0], row[1], row[2], row[3], row[4], row[6], row[12]});
    md << markdownTable(brief);
  }
  TextTable missing;  // the runs.csv rows of runs without a result (collected early)
  missing.header = {"dataset", "camera model", "N_f", "run", "seed", "directory"};
  missing.label_columns = missing.header.size();
  for (const auto& row : runsTable(cells, false).rows)
    if (row[5] == "missing")
      missing.rows.push_back({row[0], row[1], row[2], row[3], row[4],
                              fs::path(row[12]).parent_path().string()});
  if (!missing.rows.empty())
    md << "\n## Missing runs\n\n"
       << missing.rows.size() << " runs have not finished (`missing` in `runs.csv`):\n\n"
       << markdownTable(missing);
  writeFile(out / "runs.csv", csvTable(runsTable(cells, false)));
  writeFile(out / "tables.md", md.str());
}

}  // namespace omnidso::cli
