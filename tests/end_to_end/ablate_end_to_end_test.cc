// `omnidso ablate` as a user runs it (label `slow`): two tiny rendered room185 sequences,
// native and a 90° pinhole crop, N_f 5 and 3, two runs each — 16 `omnidso run` processes,
// two at a time. Checks that every table and plot is written with the right rows and
// columns, that the tables agree with the runs (failed runs marked, medians over the rest),
// and that a second invocation runs nothing again. The odometry's accuracy is not judged.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include <omnidso/synth/dataset_writer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "core/temp_dir.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

using CsvRows = std::vector<std::vector<std::string>>;

// RFC 4180: quoted fields may hold commas and doubled quotes.
CsvRows readCsv(const std::string& path) {
  std::ifstream in(path);
  CsvRows rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        fields.emplace_back();
      } else {
        fields.back() += c;
      }
    }
    rows.push_back(fields);
  }
  return rows;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void renderRoom(const std::string& dir, int size) {
  synth::SyntheticSequenceConfig config = synth::presetConfig("room185");
  config.frames = 60;
  config.width = config.height = size;
  synth::SyntheticSequence sequence(config);
  synth::writeSyntheticDataset(sequence, dir);
}

// Every file under runs/ with its modification time: a rerun would change them.
std::map<std::string, fs::file_time_type> runFiles(const std::string& out) {
  std::map<std::string, fs::file_time_type> files;
  for (const auto& entry : fs::recursive_directory_iterator(out + "/runs"))
    if (entry.is_regular_file()) files[entry.path().string()] = entry.last_write_time();
  return files;
}

TEST(AblateEndToEnd, TwoRenderedSequencesGiveCompleteTablesAndPlotsAndResume) {
  test::TempDir dir;
  renderRoom(dir.file("room_a"), 240);
  renderRoom(dir.file("room_b"), 320);
  const std::string out = dir.file("ablation");
  const std::string command = std::string(OMNIDSO_EXECUTABLE) + " ablate --datasets " +
                              dir.file("room_a") + "," + dir.file("room_b") +
                              " --camera-models native,pinhole-crop:90 --keyframes 5,3 --runs 2"
                              " --jobs 2 --timeout 300 --quiet --out " +
                              out;
  ASSERT_EQ(std::system((command + " > " + dir.file("first.log") + " 2>&1").c_str()), 0)
      << readFile(dir.file("first.log"));

  // Every run recorded, with seeds 0 and 1, and its result.json agreeing.
  const CsvRows runs = readCsv(out + "/runs.csv");
  ASSERT_EQ(runs.size(), 1u + 16u);
  ASSERT_EQ(runs[0][5], "status");
  std::map<std::string, int> ok_runs;  // "dataset model N_f" → successful runs
  for (size_t i = 1; i < runs.size(); ++i) {
    const auto& r = runs[i];
    EXPECT_EQ(r[4], std::to_string(std::stoi(r[3]) - 1)) << "seed of run " << r[3];
    const std::string run_dir = out + "/" + fs::path(r[12]).parent_path().string();
    const nlohmann::json result = nlohmann::json::parse(readFile(run_dir + "/result.json"));
    EXPECT_EQ(result["status"], r[5]);
    EXPECT_TRUE(fs::is_regular_file(run_dir + "/log.txt"));
    if (r[5] == "ok") {
      EXPECT_FALSE(r[7].empty()) << "a successful run has an RMSE";
      ++ok_runs[r[0] + " " + r[1] + " " + r[2]];
    } else {
      EXPECT_FALSE(r[6].empty()) << "a failed run has a reason";
    }
  }
  std::cout << "successful runs per cell:";
  for (const auto& [cell, n] : ok_runs) std::cout << " [" << cell << ": " << n << "]";
  std::cout << "\n";

  // Table I: a row per dataset, RMSE/used/runs/%/scale drift per camera model.
  const CsvRows t1 = readCsv(out + "/table1_rmse.csv");
  ASSERT_EQ(t1.size(), 3u);
  EXPECT_EQ(t1[0].size(), 1u + 2u * 5u);
  EXPECT_EQ(t1[0][5], "native scale_drift_percent");
  EXPECT_EQ(t1[1][0], "room_a");
  EXPECT_EQ(t1[2][0], "room_b");
  const CsvRows t2 = readCsv(out + "/table2_length.csv");
  ASSERT_EQ(t2.size(), 3u);
  EXPECT_EQ(t2[1][1], "60");
  EXPECT_GT(std::stod(t2[1][3]), 0.1) << "ground-truth length";
  // Table III agrees with the runs: runs_used is the number of successful runs, and a cell
  // without one has no value.
  const CsvRows t3 = readCsv(out + "/table3_rmse_per_keyframes.csv");
  ASSERT_EQ(t3.size(), 1u + 4u);
  ASSERT_EQ(t3[0].size(), 2u + 2u * 3u);
  for (size_t i = 1; i < t3.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const std::string cell = t3[i][0] + " " + t3[i][1] + " " + (k == 0 ? "5" : "3");
      EXPECT_EQ(t3[i][2 + 3 * k + 1], std::to_string(ok_runs[cell])) << cell;
      EXPECT_EQ(t3[i][2 + 3 * k + 2], "2") << cell;
      EXPECT_EQ(t3[i][2 + 3 * k].empty(), ok_runs[cell] == 0) << cell;
    }
  const CsvRows t4 = readCsv(out + "/table4_rmse_differences.csv");
  ASSERT_EQ(t4.size(), 1u + 4u);
  EXPECT_EQ(t4[0], (std::vector<std::string>{"dataset", "camera_model", "Kf3-Kf5 m"}));
  const CsvRows t5 = readCsv(out + "/table5_timing.csv");
  ASSERT_EQ(t5.size(), 1u + 4u);
  EXPECT_EQ(t5[0].size(), 6u);

  // tables.md holds all five tables, the rule, and marks failures.
  const std::string md = readFile(out + "/tables.md");
  for (const char* heading : {"## Table I:", "## Table II:", "## Table III:", "## Table IV:",
                              "## Table V:", "## Failed runs", "median over the successful runs"})
    EXPECT_NE(md.find(heading), std::string::npos) << heading;
  const size_t failed = runs.size() - 1 - [&] {
    size_t n = 0;
    for (const auto& [cell, k] : ok_runs) n += k;
    return n;
  }();
  const std::string failed_line = failed ? std::to_string(failed) + " failed runs" : "None.";
  EXPECT_NE(md.find(failed_line), std::string::npos) << failed_line;

  for (const char* name : {"room_a", "room_b"})
    for (const char* kind : {"_trajectories.png", "_ate.png"}) {
      const std::string path = out + "/plots/" + name + kind;
      const cv::Mat image = cv::imread(path);
      EXPECT_FALSE(image.empty()) << path;
    }

  // Resumed: nothing runs again, no run's file changes, the tables are the same.
  const auto before = runFiles(out);
  ASSERT_EQ(std::system((command + " > " + dir.file("second.log") + " 2>&1").c_str()), 0);
  EXPECT_NE(readFile(dir.file("second.log")).find("16 finished earlier"), std::string::npos)
      << readFile(dir.file("second.log"));
  EXPECT_EQ(runFiles(out), before);
  EXPECT_EQ(readFile(out + "/tables.md"), md);
}

}  // namespace
}  // namespace omnidso
