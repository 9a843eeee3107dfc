// Medians over successful runs, failure annotations, and the shape of Tables I–V.
#include <gtest/gtest.h>

#include <omnidso/cli/ablation_report.hpp>
#include <omnidso/cli/ablation_tables.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso::cli {
namespace {

RunResult ok(int run, double rmse, double tracking_ms = 10) {
  RunResult r;
  r.run = run;
  r.seed = run - 1;
  r.ok = true;
  r.rmse_m = rmse;
  r.rmse_percent_of_path = 100 * rmse;
  r.scale_drift_percent = -1000 * rmse;  // -10, -30, -20 % for the cell below
  r.tracking_ms = tracking_ms;
  r.mapping_ms = 10 * tracking_ms;
  return r;
}

RunResult failed(int run, const std::string& why) {
  RunResult r;
  r.run = run;
  r.seed = run - 1;
  r.failure = why;
  r.rmse_m = 99.0;  // a failed run's ATE (of its longest segment) never counts
  return r;
}

AblationCell cell(const std::string& dataset, const std::string& model, int keyframes) {
  return {dataset, "/data/" + dataset, model, keyframes};
}

// Two datasets × {native, pinhole-crop:90} × N_f {7, 3}, 3 runs per cell.
std::vector<CellSummary> exampleCells() {
  std::vector<CellSummary> cells;
  for (const std::string dataset : {"seqA", "seqB"})
    for (const std::string model : {"native", "pinhole-crop:90"})
      for (int n : {7, 3}) {
        std::vector<RunResult> runs = {ok(1, 0.010), ok(2, 0.030), ok(3, 0.020)};
        if (model == "native" && n == 3) runs[1] = failed(2, "lost tracking");
        if (model == "pinhole-crop:90" && n == 3 && dataset == "seqB")
          runs = {failed(1, "timeout after 60 s"), failed(2, "not initialised"),
                  failed(3, "exit status 3")};
        cells.push_back(summarizeCell(cell(dataset, model, n), runs));
      }
  return cells;
}

std::vector<DatasetFacts> exampleFacts() {
  return {{"seqA", 100, 5.0, 3.5}, {"seqB", 80, 4.0, 2.25}};
}

TEST(AblationTablesTest, MedianIsTheMiddleOrTheMeanOfTheTwoMiddleValues) {
  EXPECT_FALSE(medianOf({}));
  EXPECT_DOUBLE_EQ(*medianOf({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(*medianOf({4, 1, 3, 2}), 2.5);
}

TEST(AblationTablesTest, CellMedianLeavesFailedRunsOutAndCountsThem) {
  const CellSummary s = summarizeCell(cell("seqA", "native", 7),
                                      {ok(1, 0.04), failed(2, "crash"), ok(3, 0.01), ok(4, 0.02)});
  EXPECT_EQ(s.succeeded, 3u);
  EXPECT_EQ(s.runs.size(), 4u);
  EXPECT_DOUBLE_EQ(*s.rmse_m, 0.02);
  ASSERT_TRUE(s.median_run);
  EXPECT_EQ(s.runs[*s.median_run].run, 4);  // the run with the median RMSE

  const CellSummary even = summarizeCell(cell("seqA", "native", 7), {ok(1, 0.04), ok(2, 0.01)});
  EXPECT_DOUBLE_EQ(*even.rmse_m, 0.025);
  EXPECT_EQ(even.runs[*even.median_run].run, 2);  // the lower of the two middle runs

  const CellSummary none =
      summarizeCell(cell("seqA", "native", 7), {failed(1, "a"), failed(2, "b")});
  EXPECT_EQ(none.succeeded, 0u);
  EXPECT_FALSE(none.rmse_m);
  EXPECT_FALSE(none.median_run);
}

TEST(AblationTablesTest, TablesHaveARowPerDatasetAndMarkFailures) {
  const std::vector<AblationTable> tables = ablationTables(exampleFacts(), exampleCells());
  ASSERT_EQ(tables.size(), 5u);
  const AblationTable& t1 = tables[0];
  EXPECT_EQ(t1.csv_name, "table1_rmse.csv");
  ASSERT_EQ(t1.markdown.rows.size(), 2u);
  EXPECT_EQ(t1.markdown.header.size(), 1u + 2u * 3u);  // dataset + (RMSE, %, drift) per model
  EXPECT_EQ(t1.markdown.rows[0][1], "0.0200");         // median of 0.01, 0.03, 0.02 at N_f 7
  EXPECT_EQ(t1.markdown.rows[0][3], "-20.00");         // median scale drift of the same runs
  EXPECT_EQ(t1.csv.rows[0][1], "0.02");
  EXPECT_EQ(t1.csv.rows[0][5], "-20");

  const AblationTable& t2 = tables[1];
  EXPECT_EQ(t2.markdown.rows[1], (std::vector<std::string>{"seqB", "80", "4.0", "2.25"}));

  const AblationTable& t3 = tables[2];
  ASSERT_EQ(t3.markdown.rows.size(), 4u);  // dataset × camera model
  EXPECT_EQ(t3.markdown.header,
            (std::vector<std::string>{"dataset", "camera model", "Kf7 [m]", "Kf3 [m]"}));
  EXPECT_EQ(t3.markdown.rows[0][3], "0.0150 (failed 1/3)");  // native Kf3: median of 0.01, 0.02
  EXPECT_EQ(t3.markdown.rows[3][3], "failed 3/3");           // seqB pinhole Kf3
  EXPECT_EQ(t3.csv.rows[3][std::size_t(2 + 3)], "");         // no value, 0 of 3 runs used
  EXPECT_EQ(t3.csv.rows[3][std::size_t(2 + 4)], "0");

  const AblationTable& t4 = tables[3];
  EXPECT_EQ(t4.markdown.header.size(), 3u);  // one difference column: Kf3 − Kf7
  EXPECT_EQ(t4.markdown.rows[0][2], "-0.0050 (Kf3 failed 1/3)");
  EXPECT_EQ(t4.markdown.rows[3][2], "n/a (Kf3 failed 3/3)");
  EXPECT_EQ(t4.csv.rows[3][2], "");

  const AblationTable& t5 = tables[4];
  ASSERT_EQ(t5.markdown.rows.size(), 4u);  // camera model × N_f
  EXPECT_EQ(t5.markdown.rows[3][0], "pinhole-crop:90");
  EXPECT_EQ(t5.markdown.rows[3][2], "10.0 (failed 3/6)");  // pooled over both datasets
  EXPECT_EQ(t5.csv.rows[3][4], "3");
  EXPECT_EQ(t5.csv.rows[3][5], "6");
}

TEST(AblationTablesTest, MarkdownAndCsvAreWellFormed) {
  TextTable t{{"name", "value"}, {{"a|b", "1"}, {"say \"hi\", twice", "2"}}};
  const std::string md = markdownTable(t);
  EXPECT_NE(md.find("a\\|b"), std::string::npos);
  EXPECT_NE(md.find("| :---"), std::string::npos);
  EXPECT_EQ(csvTable(t), "name,value\na|b,1\n\"say \"\"hi\"\", twice\",2\n");
  t.rows.push_back({"short"});
  EXPECT_THROW(markdownTable(t), Error);
}

TEST(AblationTablesTest, RunsTableListsEveryRunWithSeedAndReason) {
  const std::vector<CellSummary> cells = exampleCells();
  const TextTable all = runsTable(cells, false);
  EXPECT_EQ(all.rows.size(), 2u * 2u * 2u * 3u);
  const TextTable failures = runsTable(cells, true);
  ASSERT_EQ(failures.rows.size(), 2u + 3u);  // native Kf3 of both datasets, seqB pinhole Kf3
  EXPECT_EQ(failures.rows[0][5], "failed");
  EXPECT_EQ(failures.rows[0][6], "lost tracking");
  EXPECT_EQ(failures.rows[0][4], "1");  // run 2's seed
  EXPECT_NE(failureRuleText(3).find("median over the successful runs"), std::string::npos);
}

}  // namespace
}  // namespace omnidso::cli
