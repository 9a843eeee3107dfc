// Trajectory file I/O: bit-exact TUM round trip, the three formats, and every malformed
// case rejected with an Error naming file and line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <omnidso/core/error.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <random>
#include <string>

#include "core/temp_dir.hpp"
#include "test_data.hpp"

namespace omnidso {
namespace {

// Each test writes its files into its own temporary directory (temp_dir.hpp: named after
// the test and the process, since ctest runs tests in parallel processes), removed again
// when the test ends.
class TrajectoryIo : public ::testing::Test {
 protected:
  std::string writeTempFile(const std::string& suffix, const std::string& content) {
    const std::string path = temp_.file("trajectory_" + std::to_string(num_files_++) + suffix);
    std::ofstream(path) << content;
    return path;
  }

  // Expects reading to throw an Error whose message starts with "PATH:LINE:".
  void expectErrorAtLine(const std::string& content, TrajectoryFormat format, int line,
                         const std::string& what,
                         TimestampPolicy policy = TimestampPolicy::kTolerant) {
    const std::string path = writeTempFile(".txt", content);
    try {
      readTrajectoryFile(path, format, policy);
      ADD_FAILURE() << "no error for: " << what;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(path + ":" + std::to_string(line) + ":", 0), 0u)
          << what << ": " << message;
    }
  }

 private:
  test::TempDir temp_;
  int num_files_ = 0;
};

TEST_F(TrajectoryIo, TumRoundTripIsBitExact) {
  std::mt19937 rng(42);
  std::normal_distribution<double> normal(0.0, 3.0);
  Trajectory trajectory;
  // Large Unix-time stamps (9 decimals suffice) and small ones (need 17 digits).
  double t = 1403715273.26214;
  for (int i = 0; i < 50; ++i) {
    SE3<double>::Tangent xi;
    for (int k = 0; k < 6; ++k) xi(k) = normal(rng);
    trajectory.push_back({t, SE3d::exp(xi)});
    t += (i == 25) ? 0.1 / 3.0 : 0.05;
  }
  trajectory.insert(trajectory.begin(), StampedPose{0.1 / 3.0, SE3d::exp(SE3d::Tangent::Ones())});
  const std::string path = writeTempFile(".txt", "");
  writeTrajectoryTum(path, trajectory);
  const Trajectory read = readTrajectoryTum(path);
  ASSERT_EQ(read.size(), trajectory.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].timestamp, trajectory[i].timestamp) << i;
    double a[7], b[7];
    read[i].pose.toParameters(a);
    trajectory[i].pose.toParameters(b);
    for (int k = 0; k < 7; ++k) EXPECT_EQ(a[k], b[k]) << i << " " << k;
  }
}

TEST_F(TrajectoryIo, TumSkipsCommentsAndBlankLinesAndAcceptsCommas) {
  const std::string path = writeTempFile(".txt",
                                         "# timestamp tx ty tz qx qy qz qw\n"
                                         "\n"
                                         "1.0 1 2 3 0 0 0 1\n"
                                         "  # indented comment\n"
                                         "2.5,4,5,6,0,0,0.7071067811865476,0.7071067811865476\r\n");
  const Trajectory trajectory = readTrajectoryTum(path);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_EQ(trajectory[1].timestamp, 2.5);
  EXPECT_EQ(trajectory[1].pose.translation(), Eigen::Vector3d(4, 5, 6));
  // 90° about z maps x to y; the quaternion is unit to 1e-16, so 1e-12 is generous.
  EXPECT_LT((trajectory[1].pose.rotation() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY())
                .norm(),
            1e-12);
}

TEST_F(TrajectoryIo, SlightlyNonUnitQuaternionIsNormalised) {
  // Six printed decimals leave |q| off by ~1e-6: accepted and normalised.
  const std::string path = writeTempFile(".txt", "0 0 0 0 -0.824237 -0.106942 -0.551702 0.069434\n");
  const Trajectory trajectory = readTrajectoryTum(path);
  EXPECT_NEAR(trajectory[0].pose.rotation().norm(), 1.0, 1e-15);
}

TEST_F(TrajectoryIo, KittiUsesLineIndexAsTimestamp) {
  const std::string path = writeTempFile(
      ".txt",
      "1 0 0 0 0 1 0 0 0 0 1 0\n"
      "0 -1 0 1.5 1 0 0 2.5 0 0 1 3.5\n");
  const Trajectory trajectory = readTrajectory(path, TrajectoryFormat::kKitti);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_EQ(trajectory[0].timestamp, 0.0);
  EXPECT_EQ(trajectory[1].timestamp, 1.0);
  EXPECT_EQ(trajectory[1].pose.translation(), Eigen::Vector3d(1.5, 2.5, 3.5));
  Eigen::Matrix3d expected;
  expected << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  // An exact rotation matrix survives the polar projection to rounding (1e-15).
  EXPECT_LT((trajectory[1].pose.rotationMatrix() - expected).norm(), 1e-15);
}

TEST_F(TrajectoryIo, EurocCsvConvertsNanosecondsAndWxyzOrder) {
  const std::string path = writeTempFile(
      ".csv",
      "#timestamp [ns], p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
      "q_RS_y [], q_RS_z [], v_x, v_y, v_z\n"
      "1403715273262142976,0.878612,2.142470,0.947262,0.060514,-0.828459,-0.058956,-0.553641,"
      "0.009474,-0.014009,-0.002145\n"
      "1403715273267142912,0.878628,2.142392,0.947251,0.060514,-0.828458,-0.058955,-0.553643,"
      "0.009474,-0.014009,-0.002145\n");
  const Trajectory trajectory = readTrajectory(path, TrajectoryFormat::kEuroc);
  ASSERT_EQ(trajectory.size(), 2u);
  // A double near 1.4e9 s resolves 2.4e-7 s, the bound on the conversion error.
  EXPECT_NEAR(trajectory[0].timestamp, 1403715273.262142976, 2.4e-7);
  EXPECT_NEAR(trajectory[1].timestamp - trajectory[0].timestamp, 0.004999936, 5e-7);
  EXPECT_EQ(trajectory[0].pose.translation(), Eigen::Vector3d(0.878612, 2.142470, 0.947262));
  // Printed to 6 decimals: normalisation changes components by at most ~1e-6.
  EXPECT_NEAR(trajectory[0].pose.rotation().w(), 0.060514, 2e-6);
  EXPECT_NEAR(trajectory[0].pose.rotation().x(), -0.828459, 2e-6);
}

TEST_F(TrajectoryIo, MalformedFilesNameFileAndLine) {
  const std::string ok = "# header\n1 0 0 0 0 0 0 1\n";
  expectErrorAtLine(ok + "2 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "7 columns");
  expectErrorAtLine(ok + "2 0 0 0 0 0 0 1 9\n", TrajectoryFormat::kTum, 3, "9 columns");
  expectErrorAtLine(ok + "2 0 x 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "non-numeric");
  expectErrorAtLine(ok + "2 0 1e 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "trailing garbage");
  expectErrorAtLine(ok + "2 0 nan 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "nan");
  expectErrorAtLine(ok + "2 0 0 inf 0 0 0 1\n", TrajectoryFormat::kTum, 3, "inf");
  expectErrorAtLine(ok + "2 0 0 0 0 0 0 1.01\n", TrajectoryFormat::kTum, 3, "non-unit q");
  expectErrorAtLine(ok + "2 0 0 0 0 0 0 0\n", TrajectoryFormat::kTum, 3, "zero quaternion");
  expectErrorAtLine(ok + "2 0 0 0 0 0 0 1\n2 0 0\n", TrajectoryFormat::kTum, 4, "truncated line");
  expectErrorAtLine(ok + "1 0 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "repeated stamp",
                    TimestampPolicy::kStrict);
  expectErrorAtLine(ok + "0.5 0 0 0 0 0 0 1\n", TrajectoryFormat::kTum, 3, "stamp backwards",
                    TimestampPolicy::kStrict);
  expectErrorAtLine("1 0 0 0 0 1 0 0 0 0 1\n", TrajectoryFormat::kKitti, 1, "kitti 11 columns");
  expectErrorAtLine("1 0 0 0 0 1 0 0 0 0 2 0\n", TrajectoryFormat::kKitti, 1, "kitti not a rotation");
  expectErrorAtLine("1 0 0 0 0 0 0\n", TrajectoryFormat::kEuroc, 1, "euroc 7 columns");
  expectErrorAtLine("1,0,0,0,1,0,0,0,abc\n", TrajectoryFormat::kEuroc, 1, "euroc extra non-numeric");
}

// TUM RGB-D's fr2/desk ground truth repeats a timestamp (line 10863) with another pose:
// the first is kept, as evo's nearest-stamp association would match it, and the drop is
// reported; strict mode refuses the file.
TEST_F(TrajectoryIo, RepeatedTimestampKeepsTheFirstPoseAndWarns) {
  const std::string path = writeTempFile(".txt",
                                         "# ground truth trajectory\n"
                                         "1311868229.5660 1 0 0 0 0 0 1\n"
                                         "1311868229.5760 2 0 0 0 0 0 1\n"
                                         "1311868229.5760 9 0 0 0 0 0 1\n"
                                         "1311868229.5760 8 0 0 0 0 0 1\n"
                                         "1311868229.5860 3 0 0 0 0 0 1\n");
  const TrajectoryFile file = readTrajectoryFile(path, TrajectoryFormat::kTum);
  ASSERT_EQ(file.poses.size(), 3u);
  EXPECT_EQ(file.poses[1].pose.translation().x(), 2.0);
  EXPECT_EQ(file.poses[2].pose.translation().x(), 3.0);
  EXPECT_EQ(file.repeated_timestamps_dropped, 2u);
  EXPECT_FALSE(file.was_sorted);
  ASSERT_EQ(file.warnings.size(), 1u);
  EXPECT_NE(file.warnings[0].find("2 pose(s)"), std::string::npos) << file.warnings[0];
  EXPECT_NE(file.warnings[0].find("line 4"), std::string::npos) << file.warnings[0];
  EXPECT_EQ(readTrajectory(path, TrajectoryFormat::kTum).size(), 3u);
}

TEST_F(TrajectoryIo, UnsortedLinesAreSortedWithAWarning) {
  const std::string path = writeTempFile(".csv",
                                         "\xEF\xBB\xBF#timestamp [ns], x, y, z, qw, qx, qy, qz\r\n"
                                         "3000000000,3,0,0,1,0,0,0\r\n"
                                         "1000000000,1,0,0,1,0,0,0\r\n"
                                         "\r\n"
                                         "2000000000,2,0,0,1,0,0,0\r\n"
                                         "1000000000,7,0,0,1,0,0,0\r\n");
  const TrajectoryFile file = readTrajectoryFile(path, TrajectoryFormat::kEuroc);
  ASSERT_EQ(file.poses.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(file.poses[i].timestamp, static_cast<double>(i + 1));
    // Of the two poses at 1 s, the one earlier in the file (x = 1) is kept.
    EXPECT_EQ(file.poses[i].pose.translation().x(), static_cast<double>(i + 1));
  }
  EXPECT_TRUE(file.was_sorted);
  EXPECT_EQ(file.repeated_timestamps_dropped, 1u);
  EXPECT_EQ(file.warnings.size(), 2u);
}

TEST_F(TrajectoryIo, ScientificNotationAndPlusSignsAreNumbers) {
  const std::string path = writeTempFile(".txt",
                                         "1.311868229566E+09 +1e-3 -2.5e0 0 0 0 0 1.0E0\n"
                                         "1.311868229576e9 1E-3 0 0 0 0 0 1\n");
  const Trajectory trajectory = readTrajectoryTum(path);
  ASSERT_EQ(trajectory.size(), 2u);
  EXPECT_EQ(trajectory[0].timestamp, 1311868229.566);
  EXPECT_EQ(trajectory[0].pose.translation(), Eigen::Vector3d(1e-3, -2.5, 0));
}

TEST_F(TrajectoryIo, EmptyAndMissingFilesNameTheFile) {
  const std::string path = writeTempFile(".txt", "# only a comment\n\n");
  try {
    readTrajectoryTum(path);
    ADD_FAILURE() << "no error for an empty file";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
  }
  EXPECT_THROW(readTrajectoryTum(path + ".does_not_exist"), Error);
  EXPECT_THROW(parseTrajectoryFormat("bag"), Error);
}

TEST_F(TrajectoryIo, ReadsRealEurocGroundTruth) {
  const auto dir = test::sharedDataDir("trajectories");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("trajectories");
  const Trajectory trajectory =
      readTrajectoryTum((*dir / "euroc_v1_01_easy_imu_groundtruth.txt").string());
  EXPECT_EQ(trajectory.size(), 2895u);  // 2896 lines minus the header
  EXPECT_EQ(trajectory.front().timestamp, 1403715273.26214);
}

}  // namespace
}  // namespace omnidso
