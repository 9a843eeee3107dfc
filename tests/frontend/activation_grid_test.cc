// Activation's occupancy grid (activation_grid.hpp): its cell size spreads num_points over the
// content, a cell is free until a point lands in it, and nothing but the cells bounds
// activation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/activation_grid.hpp>

namespace omnidso {
namespace {

TEST(ActivationGrid, CellsSpreadNumPointsOverTheContent) {
  // 480 × 480 fully covered, 2000 points: c = √(230400 / 2000) = 10.733 px.
  const ActivationGrid full(480, 480, 480.0 * 480.0, 2000);
  EXPECT_NEAR(full.cellSize(), std::sqrt(230400.0 / 2000.0), 1e-12);
  // A disc of a quarter of the area: cells half as wide, the same number on the content.
  const ActivationGrid disc(480, 480, 480.0 * 480.0 / 4.0, 2000);
  EXPECT_NEAR(disc.cellSize(), full.cellSize() / 2.0, 1e-12);
  // Never below 2 px, whatever the density asked for.
  EXPECT_EQ(ActivationGrid(480, 480, 100.0, 2000).cellSize(), 2.0);
}

TEST(ActivationGrid, ACellIsOccupiedOnceAPointLandsInIt) {
  ActivationGrid grid(100, 100, 100.0 * 100.0, 100);  // 10 px cells
  const Eigen::Vector2d a(12.0, 37.0), same_cell(19.9, 30.1), next_cell(20.1, 30.1);
  EXPECT_FALSE(grid.occupied(a));
  grid.occupy(a);
  EXPECT_TRUE(grid.occupied(same_cell));
  EXPECT_FALSE(grid.occupied(next_cell));
  grid.occupy(same_cell);  // already occupied: counted once
  EXPECT_EQ(grid.numOccupied(), 1);
}

// The property the odometry relies on: a window whose points crowd into a few cells — on a
// forward path the far points around the focus of expansion, seen from every keyframe — does
// not hold back a candidate in an empty part of the image, however many points it holds.
TEST(ActivationGrid, CrowdedPointsElsewhereDoNotBlockAFreeCell) {
  const int num_points = 200;
  ActivationGrid grid(200, 200, 200.0 * 200.0, num_points);  // 14.1 px cells
  for (int i = 0; i < 5 * num_points; ++i)
    grid.occupy(Eigen::Vector2d(86.0 + 0.01 * i, 86.0 + 0.005 * i));  // 5 N_p points, 1 cell
  EXPECT_EQ(grid.numOccupied(), 1);
  EXPECT_FALSE(grid.occupied(Eigen::Vector2d(5.0, 190.0)));
  EXPECT_FALSE(grid.occupied(Eigen::Vector2d(190.0, 5.0)));
}

// The activation density's cell scale s (activation_density.hpp): c = max(2, s · √(A / N_p)).
// In a turn the window's points fill the strip the newest keyframe shares with the older
// ones, one per full cell; at s = 1/2 a candidate between two of them gets a cell of its own.
TEST(ActivationGrid, ACellScaleBelowOneFreesCellsBetweenTheWindowsPoints) {
  const ActivationGrid half(480, 480, 480.0 * 480.0, 2000, 0.5);
  EXPECT_NEAR(half.cellSize(), 0.5 * std::sqrt(230400.0 / 2000.0), 1e-12);
  EXPECT_EQ(ActivationGrid(480, 480, 480.0 * 480.0, 2000, 0.0).cellSize(), 2.0);  // the floor

  ActivationGrid full(100, 100, 100.0 * 100.0, 100);        // 10 px cells
  ActivationGrid finer(100, 100, 100.0 * 100.0, 100, 0.5);  // 5 px cells
  for (int row = 0; row < 10; ++row)
    for (int col = 0; col < 3; ++col) {  // a strip 30 px wide, a point in each full cell
      const Eigen::Vector2d u(10.0 * col + 2.0, 10.0 * row + 2.0);
      full.occupy(u);
      finer.occupy(u);
    }
  const Eigen::Vector2d between(17.0, 47.0);  // 7 px from the four nearest points
  EXPECT_TRUE(full.occupied(between));
  EXPECT_FALSE(finer.occupied(between));
  EXPECT_THROW(ActivationGrid(100, 100, 1e4, 100, -0.1), Error);
  EXPECT_THROW(ActivationGrid(100, 100, 1e4, 100, std::numeric_limits<double>::quiet_NaN()),
               Error);
}

TEST(ActivationGrid, PixelsOutsideTheImageAreNeverFree) {
  ActivationGrid grid(100, 80, 8000.0, 80);  // 10 px cells, 11 × 9 of them
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Vector2d& u :
       {Eigen::Vector2d(-0.5, 10.0), Eigen::Vector2d(10.0, -3.0), Eigen::Vector2d(1e6, 10.0),
        Eigen::Vector2d(10.0, 1e6), Eigen::Vector2d(nan, 10.0)}) {
    EXPECT_FALSE(grid.contains(u));
    EXPECT_TRUE(grid.occupied(u));
    grid.occupy(u);  // ignored
  }
  EXPECT_EQ(grid.numOccupied(), 0);
  EXPECT_TRUE(grid.contains(Eigen::Vector2d(99.9, 79.9)));
}

}  // namespace
}  // namespace omnidso
