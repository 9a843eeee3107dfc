// points.ply written while the odometry runs: the header's vertex count matches the vertices,
// the body file beside it is gone afterwards, and an abandoned writer leaves nothing behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/cli/ply_point_writer.hpp>
#include <omnidso/core/error.hpp>
#include <string>
#include <vector>

#include "core/temp_dir.hpp"

namespace omnidso::cli {
namespace {

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// An odometry that has seen no frame holds no points: finish() adds nothing of its own.
Odometry emptyOdometry() {
  return Odometry(Camera::create("pinhole", Eigen::Vector4d(100, 100, 50, 50), 100, 100));
}

TEST(PlyPointWriter, HeaderCountsTheVerticesThatFollowIt) {
  test::TempDir dir;
  const std::string path = dir.file("points.ply");
  PlyPointWriter writer(path);
  writer.add({Eigen::Vector3f(1.f, -2.5f, 3.25f), 128.5f, 0});
  writer.add({Eigen::Vector3f(0.f, 0.f, 1e-3f), 7.f, 2});
  writer.finish(emptyOdometry());
  EXPECT_EQ(writer.count(), 2u);
  const std::vector<std::string> l = lines(path);
  ASSERT_EQ(l.size(), 9u + 2u);
  EXPECT_EQ(l[0], "ply");
  EXPECT_EQ(l[2], "element vertex 2");
  EXPECT_EQ(l[8], "end_header");
  EXPECT_EQ(l[9], "1.000000 -2.500000 3.250000 128.50 0");
  EXPECT_EQ(l[10], "0.000000 0.000000 0.001000 7.00 2");
  EXPECT_FALSE(std::filesystem::exists(path + ".body"));
}

TEST(PlyPointWriter, EmptyMapGivesAValidFileWithNoVertices) {
  test::TempDir dir;
  const std::string path = dir.file("points.ply");
  PlyPointWriter writer(path);
  writer.finish(emptyOdometry());
  const std::vector<std::string> l = lines(path);
  ASSERT_EQ(l.size(), 9u);
  EXPECT_EQ(l[2], "element vertex 0");
  EXPECT_EQ(l.back(), "end_header");
}

TEST(PlyPointWriter, AbandonedWriterLeavesNoFile) {
  test::TempDir dir;
  const std::string path = dir.file("points.ply");
  {
    PlyPointWriter writer(path);
    writer.add({Eigen::Vector3f(1.f, 2.f, 3.f), 1.f, 0});
    EXPECT_TRUE(std::filesystem::exists(path + ".body"));
  }  // a run that failed: no finish()
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".body"));
}

TEST(PlyPointWriter, UnwritableDirectoryFailsAtOnce) {
  test::TempDir dir;
  EXPECT_THROW(PlyPointWriter(dir.file("missing/points.ply")), Error);
}

}  // namespace
}  // namespace omnidso::cli
