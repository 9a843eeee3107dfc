#pragma once
// The tables of `omnidso ablate`, after the paper's (Matsuki et al. 2018):
//   Table I    keyframe ATE RMSE (m and % of the path) per dataset × camera model, at the
//              reference N_f (the first of --keyframes)
//   Table II   ground-truth trajectory length per dataset
//   Table III  RMSE per dataset × camera model × N_f
//   Table IV   RMSE differences of every other N_f to the reference (Kf5 − Kf7, Kf3 − Kf7)
//   Table V    tracking ms per frame and mapping ms per keyframe per camera model × N_f
// (written by ablation_report.hpp).
//
// Rule: a value is the median over the successful runs of its cell; "(failed k/n)" after it
// says that k of the n runs failed and were left out; "failed n/n" that none succeeded;
// "(missing m/n)" that m runs have not finished (yet), when tables are collected early.
// Table V pools the runs of all datasets of a camera model × N_f.

#include <omnidso/cli/ablation_plan.hpp>
#include <omnidso/cli/ablation_run_result.hpp>
#include <omnidso/cli/text_table.hpp>
#include <optional>
#include <string>
#include <vector>

namespace omnidso::cli {

struct DatasetFacts {
  std::string name;
  size_t frames = 0;       // used by the runs (--max-frames)
  double duration_s = 0;   // of those frames
  double gt_length_m = 0;  // ground-truth path length over them
};

struct CellSummary {
  AblationCell cell;
  std::vector<RunResult> runs;  // in run order
  size_t succeeded = 0;
  size_t missing = 0;  // runs not finished (RunResult::missing)
  // Medians over the successful runs (each column its own median).
  std::optional<double> rmse_m, rmse_percent_of_path, scale_drift_percent, tracking_ms,
      mapping_ms;
  // Index into runs of the successful run with the median RMSE (the lower of the two
  // middle ones for an even count): the run drawn in the plots.
  std::optional<size_t> median_run;
};

// The median (mean of the two middle values for an even count); nullopt for none.
std::optional<double> medianOf(const std::vector<double>& values);

CellSummary summarizeCell(const AblationCell& cell, std::vector<RunResult> runs);

struct AblationTable {
  std::string csv_name;  // e.g. "table1_rmse.csv"
  std::string title;     // e.g. "Table I: keyframe ATE RMSE"
  std::string note;      // what the numbers are
  TextTable markdown;    // formatted, with failure annotations
  TextTable csv;         // plain numbers, with runs_used / runs columns
};

// Tables I–V, in that order. Cells give the axes in their order (datasets, camera models,
// N_f as planned); `datasets` holds Table II's facts by name.
std::vector<AblationTable> ablationTables(const std::vector<DatasetFacts>& datasets,
                                          const std::vector<CellSummary>& cells);

}  // namespace omnidso::cli
