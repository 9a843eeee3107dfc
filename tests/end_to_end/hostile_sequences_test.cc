// Hostile sequences (label `slow`): what a camera can deliver on a bad day — black, white,
// saturated or noise frames, a frozen frame, a 180° roll between two frames, a two-second
// gap, an exposure record jumping ×10, a camera standing still. Each is made from one
// small rendered fisheye sequence and run through the real `omnidso run`: the run must end
// with status 0 and all its outputs, every frame accounted for in timing.csv, and every
// tracking loss reported as a new segment with its event in summary.json — never a crash.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/cli/process_pool.hpp>
#include <omnidso/synth/dataset_writer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "core/temp_dir.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

// The times.txt of a dataset as (id, timestamp, exposure) rows.
struct TimesRow {
  std::string id;
  double timestamp_s;
  double exposure_ms;
};

std::vector<TimesRow> readTimes(const fs::path& dataset) {
  std::ifstream in(dataset / "times.txt");
  std::vector<TimesRow> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    TimesRow row;
    fields >> row.id >> row.timestamp_s >> row.exposure_ms;
    rows.push_back(row);
  }
  return rows;
}

void writeTimes(const fs::path& dataset, const std::vector<TimesRow>& rows) {
  std::ofstream out(dataset / "times.txt");
  out.precision(17);
  for (const TimesRow& r : rows) out << r.id << " " << r.timestamp_s << " " << r.exposure_ms << "\n";
}

cv::Mat readImage(const fs::path& dataset, const std::string& id) {
  return cv::imread((dataset / "images" / (id + ".png")).string(), cv::IMREAD_UNCHANGED);
}

void writeImage(const fs::path& dataset, const std::string& id, const cv::Mat& image) {
  cv::imwrite((dataset / "images" / (id + ".png")).string(), image);
}

// Replaces every image by f(index, image).
void mapImages(const fs::path& dataset, const std::function<cv::Mat(size_t, const cv::Mat&)>& f) {
  const std::vector<TimesRow> rows = readTimes(dataset);
  for (size_t i = 0; i < rows.size(); ++i) {
    writeImage(dataset, rows[i].id, f(i, readImage(dataset, rows[i].id)));
  }
}

// `frames` copies of the first image (ids 00000…), at the base rate, each passed through
// `vary` (the identity for a frozen frame, sensor noise for a camera standing still). The
// ground truth of the moving base no longer applies and is removed.
void repeatFirstFrame(const fs::path& dataset, int frames,
                      const std::function<cv::Mat(int, const cv::Mat&)>& vary) {
  const std::vector<TimesRow> rows = readTimes(dataset);
  const cv::Mat first = readImage(dataset, rows[0].id);
  fs::remove_all(dataset / "images");
  fs::create_directories(dataset / "images");
  fs::remove(dataset / "groundtruth.txt");
  std::vector<TimesRow> repeated;
  const double dt = rows[1].timestamp_s - rows[0].timestamp_s;
  for (int k = 0; k < frames; ++k) {
    char id[16];
    std::snprintf(id, sizeof(id), "%05d", k);
    repeated.push_back({id, rows[0].timestamp_s + k * dt, rows[0].exposure_ms});
    writeImage(dataset, id, vary(k, first));
  }
  writeTimes(dataset, repeated);
}

cv::Mat constant(const cv::Mat& like, int value) {
  return cv::Mat(like.size(), like.type(), cv::Scalar(value));
}

struct HostileCase {
  std::string name;
  std::function<void(const fs::path& dataset)> make;
};

// The base: UCM 185° at 128×128, 40 frames at 20 Hz of the hand-held room sequence.
constexpr int kBaseFrames = 40;
constexpr int kBreakAt = 20;  // where the jump, gap or exposure change happens

std::vector<HostileCase> hostileCases() {
  return {
      {"all_black", [](const fs::path& d) { mapImages(d, [](size_t, const cv::Mat& m) { return constant(m, 0); }); }},
      {"all_white", [](const fs::path& d) { mapImages(d, [](size_t, const cv::Mat& m) { return constant(m, 255); }); }},
      // ×6 gain: everything but the darkest texture clips at 255.
      {"saturated", [](const fs::path& d) {
         mapImages(d, [](size_t, const cv::Mat& m) { cv::Mat s; m.convertTo(s, -1, 6.0); return s; });
       }},
      {"pure_noise", [](const fs::path& d) {
         mapImages(d, [](size_t i, const cv::Mat& m) {
           cv::Mat noise(m.size(), m.type());
           cv::RNG rng(static_cast<uint64_t>(i) + 1);
           rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
           return noise;
         });
       }},
      {"frame_repeated_200_times", [](const fs::path& d) {
         repeatFirstFrame(d, 200, [](int, const cv::Mat& m) { return m.clone(); });
       }},
      // The principal point is the image centre, so turning the image by 180° is the camera
      // rolled by 180° about its optical axis between frame kBreakAt − 1 and kBreakAt.
      {"roll_180_degrees", [](const fs::path& d) {
         mapImages(d, [](size_t i, const cv::Mat& m) {
           if (static_cast<int>(i) < kBreakAt) return m.clone();
           cv::Mat r;
           cv::rotate(m, r, cv::ROTATE_180);
           return r;
         });
       }},
      {"two_second_gap", [](const fs::path& d) {
         std::vector<TimesRow> rows = readTimes(d);
         for (size_t i = kBreakAt; i < rows.size(); ++i) rows[i].timestamp_s += 2.0;
         writeTimes(d, rows);
         fs::remove(d / "groundtruth.txt");  // its stamps no longer match the frames
       }},
      // The recorded exposure jumps ×10 while the images do not change: the photometric
      // model sees a 10× brightness change that the affine parameters must absorb.
      {"exposure_jumps_x10", [](const fs::path& d) {
         std::vector<TimesRow> rows = readTimes(d);
         for (size_t i = kBreakAt; i < rows.size(); ++i) rows[i].exposure_ms *= 10.0;
         writeTimes(d, rows);
       }},
      // Standing still: the first frame with fresh sensor noise (σ = 2 grey levels) each time.
      {"standing_still", [](const fs::path& d) {
         repeatFirstFrame(d, kBaseFrames, [](int k, const cv::Mat& m) {
           cv::Mat noise(m.size(), CV_16SC1);
           cv::RNG rng(static_cast<uint64_t>(k) + 100);
           rng.fill(noise, cv::RNG::NORMAL, 0, 2);
           cv::Mat wide, out;
           m.convertTo(wide, CV_16SC1);
           cv::add(wide, noise, wide);
           wide.convertTo(out, CV_8UC1);
           return out;
         });
       }},
  };
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// The run's outputs agree with each other: one timing.csv row per frame, the segments of
// the tracked rows as many as summary.json counts, a "tracking lost" event per segment
// after the first.
void expectConsistentOutputs(const fs::path& out, size_t frames) {
  for (const char* file : {"frames.txt", "keyframes.txt", "points.ply", "timing.csv", "summary.json"}) {
    EXPECT_TRUE(fs::is_regular_file(out / file)) << file << " missing";
  }
  const nlohmann::json summary = nlohmann::json::parse(readFile(out / "summary.json"));
  EXPECT_EQ(summary["counts"]["frames"].get<size_t>(), frames);
  std::istringstream csv(readFile(out / "timing.csv"));
  std::string line;
  std::getline(csv, line);  // header
  size_t rows = 0, tracked = 0;
  std::set<int> segments;
  while (std::getline(csv, line)) {
    ++rows;
    std::vector<std::string> fields;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) fields.push_back(f);
    ASSERT_GE(fields.size(), 5u) << line;
    if (fields[2] == "1") {
      ++tracked;
      segments.insert(std::stoi(fields[4]));
    }
  }
  EXPECT_EQ(rows, frames);
  EXPECT_EQ(summary["counts"]["tracked_frames"].get<size_t>(), tracked);
  EXPECT_EQ(summary["counts"]["segments"].get<size_t>(), segments.size());
  size_t losses = 0;
  for (const auto& event : summary["events"]) {
    losses += event.get<std::string>().find("tracking lost") != std::string::npos;
  }
  if (!segments.empty()) {
    EXPECT_GE(losses, segments.size() - 1) << summary["events"].dump();
  }
}

TEST(HostileSequences, EveryRunEndsWithItsOutputs) {
  test::TempDir dir;
  const fs::path base = dir.file("base");
  {
    synth::SyntheticSequenceConfig config = synth::presetConfig("room185");
    config.width = config.height = 128;
    config.frames = kBaseFrames;
    config.seed = 7;
    synth::SyntheticSequence sequence(config);
    synth::writeSyntheticDataset(sequence, base.string());
  }
  const std::vector<HostileCase> cases = hostileCases();
  std::vector<cli::ProcessSpec> specs;
  for (const HostileCase& c : cases) {
    const fs::path dataset = dir.file(c.name);
    fs::copy(base, dataset, fs::copy_options::recursive);
    c.make(dataset);
    cli::ProcessSpec spec;
    spec.argv = {OMNIDSO_EXECUTABLE, "run", dataset.string(), "--out", dir.file(c.name + "_out"),
                 "--quiet", "--points", "600"};
    spec.log_path = dir.file(c.name + ".log");
    spec.timeout_s = 600;  // a hang fails the case, it does not stall the suite
    specs.push_back(spec);
  }
  const std::vector<cli::ProcessOutcome> outcomes = cli::runProcesses(specs, 2);
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].name);
    const std::string log = readFile(specs[i].log_path);
    ASSERT_TRUE(outcomes[i].succeeded()) << outcomes[i].describe() << "\n" << log;
    std::cout << cases[i].name << " (" << outcomes[i].wall_s << " s):\n" << log;
    expectConsistentOutputs(dir.file(cases[i].name + "_out"),
                            readTimes(dir.file(cases[i].name)).size());
  }
}

}  // namespace
}  // namespace omnidso
