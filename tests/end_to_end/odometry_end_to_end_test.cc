// End-to-end runs of the odometry (label `slow`): rendered fisheye sequences with ground truth,
// and the real static EuRoC clip.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/core/metrics.hpp>
#include <omnidso/synth/dataset_loading.hpp>
#include <omnidso/synth/dataset_writer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "core/temp_dir.hpp"
#include "test_data.hpp"

namespace omnidso {
namespace {

Trajectory keyframeTrajectory(const Odometry& odometry, int segment) {
  Trajectory t;
  for (const KeyframeRecord& k : odometry.keyframes())
    if (k.segment == segment) t.push_back({k.timestamp, k.T_world_cam});
  return t;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// room185 (UCM 480×480, ~185°, hand-held), 150 frames. The target is a keyframe ATE
// of at most 1 % of the path (docs/status.md: not reached yet); this test guards what the
// odometry achieves today — 1.7 % on this sequence — with a 2.5 % bound. Then `omnidso run`
// twice: byte-identical trajectories (determinism is per process: Ceres orders the blocks of
// an elimination group by address, so a second run inside one process may differ in the
// last bits).
TEST(OdometryEndToEnd, Room185FisheyeSequenceIsAccurateAndDeterministic) {
  test::TempDir dir;
  synth::SyntheticSequenceConfig config = synth::presetConfig("room185");
  config.frames = 150;
  synth::SyntheticSequence sequence(config);
  synth::writeSyntheticDataset(sequence, dir.file("room185"));
  const DatasetIndex index = openDataset(dir.file("room185"));

  const cli::DatasetRun run = cli::runOdometryOnDataset(index, cli::DatasetRunOptions{});
  const Odometry& odometry = *run.odometry;
  ASSERT_TRUE(odometry.initialized()) << odometry.initializationStatus();
  EXPECT_EQ(odometry.numSegments(), 1);
  int tracked = 0;
  for (const FrameRecord& f : odometry.frames()) tracked += f.tracked;
  EXPECT_GE(tracked, 140);

  const Trajectory gt = synth::cameraGroundTruth(index);
  const Trajectory keyframes = keyframeTrajectory(odometry, 0);
  ASSERT_GE(keyframes.size(), 10u);
  EvaluationOptions options;
  options.max_dt = 0.01;
  const EvaluationResult ate = evaluate(gt, keyframes, options);
  const double length = pathLength(gt, keyframes.front().timestamp, keyframes.back().timestamp);
  std::cout << "keyframe ATE " << ate.ate.rmse << " m over " << length << " m ("
            << 100 * ate.ate.rmse / length << " %)\n";
  EXPECT_LT(ate.ate.rmse, 0.025 * length);

  for (const std::string run : {"run1", "run2"}) {
    const std::string command = std::string(OMNIDSO_EXECUTABLE) + " run " + dir.file("room185") +
                                " --out " + dir.file(run) + " --quiet > " + dir.file(run + ".log");
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
  }
  for (const std::string file : {"frames.txt", "keyframes.txt", "points.ply"}) {
    const std::string a = readFile(dir.file("run1/" + file));
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, readFile(dir.file("run2/" + file))) << file << " differs between two runs";
  }
}

// A camera standing still (real EuRoC frames): no crash, and either no initialisation for
// lack of parallax or rotations within 1° of the first frame.
TEST(OdometryEndToEnd, StaticEurocClipDoesNotInventMotion) {
  const auto dir = test::sharedDataDir("euroc_v101_static_clip");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  const DatasetIndex index = openDataset(dir->string());
  const cli::DatasetRun run = cli::runOdometryOnDataset(index, cli::DatasetRunOptions{});
  const Odometry& odometry = *run.odometry;
  if (!odometry.initialized() && odometry.keyframes().empty()) {
    EXPECT_NE(odometry.initializationStatus().find("parallax"), std::string::npos)
        << odometry.initializationStatus();
    return;
  }
  const FrameRecord* first = nullptr;
  for (const FrameRecord& f : odometry.frames()) {
    if (!f.tracked) continue;
    if (!first) first = &f;
    const SE3d relative = odometry.framePose(*first).inverse() * odometry.framePose(f);
    EXPECT_LT(so3Log(relative.rotation()).norm() * 180 / M_PI, 1.0) << "frame " << f.index;
  }
}

}  // namespace
}  // namespace omnidso
