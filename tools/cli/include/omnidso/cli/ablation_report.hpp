#pragma once
// What `omnidso ablate` writes besides the runs: OUT/tables.md (the settings, the rule for
// failed runs, Tables I–V, and the failed runs with their reasons), one CSV per table
// (OUT/table1_rmse.csv … OUT/table5_timing.csv) and OUT/runs.csv with every run.

#include <omnidso/cli/ablation_tables.hpp>
#include <string>
#include <vector>

namespace omnidso::cli {

// One row per run: dataset, camera model, N_f, run, seed, status (ok | failed | missing),
// failure, metrics, log. failed_only: the failed runs (not the missing ones).
TextTable runsTable(const std::vector<CellSummary>& cells, bool failed_only);

// The rule for failed runs and medians, as tables.md states it.
std::string failureRuleText(int runs_per_cell);

void writeAblationReport(const std::string& out_dir, const std::string& preamble,
                         const std::vector<AblationTable>& tables,
                         const std::vector<CellSummary>& cells);

}  // namespace omnidso::cli
