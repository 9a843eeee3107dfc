// One pass of dilation of a level's inverse-distance map (reference_dilation.hpp).
#include <gtest/gtest.h>

#include <omnidso/frontend/reference_dilation.hpp>

namespace omnidso {
namespace {

// Keys are (v, u).
LevelInverseDistances at(std::initializer_list<std::pair<std::pair<int, int>, double>> points) {
  return LevelInverseDistances(points.begin(), points.end());
}

TEST(ReferenceDilation, APointSpreadsToItsFourNeighboursOfTheChosenKind) {
  const LevelInverseDistances one = at({{{5, 5}, 0.5}});
  const LevelInverseDistances diagonal =
      dilateInverseDistances(one, 12, 10, DilationNeighbours::kDiagonal);
  EXPECT_EQ(diagonal,
            at({{{4, 4}, 0.5}, {{4, 6}, 0.5}, {{5, 5}, 0.5}, {{6, 4}, 0.5}, {{6, 6}, 0.5}}));
  const LevelInverseDistances direct =
      dilateInverseDistances(one, 12, 10, DilationNeighbours::kDirect);
  EXPECT_EQ(direct,
            at({{{4, 5}, 0.5}, {{5, 4}, 0.5}, {{5, 5}, 0.5}, {{5, 6}, 0.5}, {{6, 5}, 0.5}}));
}

// A pixel between two points takes their mean; the points themselves keep their own values,
// and the new points do not spread further in the same pass.
TEST(ReferenceDilation, ANewPointIsTheMeanOfItsNeighbouringPointsOnly) {
  const LevelInverseDistances two = at({{{5, 4}, 1.0}, {{5, 6}, 3.0}});  // u = 4 and u = 6
  const LevelInverseDistances direct =
      dilateInverseDistances(two, 12, 10, DilationNeighbours::kDirect);
  ASSERT_EQ(direct.size(), 2u + 7u);  // 4 + 4 neighbours, (5, 5) shared
  EXPECT_DOUBLE_EQ(direct.at({5, 5}), 2.0);
  EXPECT_DOUBLE_EQ(direct.at({5, 4}), 1.0);
  EXPECT_DOUBLE_EQ(direct.at({5, 6}), 3.0);
  EXPECT_DOUBLE_EQ(direct.at({5, 3}), 1.0);
  EXPECT_DOUBLE_EQ(direct.at({5, 7}), 3.0);
  EXPECT_EQ(direct.count({5, 2}), 0u);  // two steps away: not in one pass

  const LevelInverseDistances diagonal =
      dilateInverseDistances(two, 12, 10, DilationNeighbours::kDiagonal);
  ASSERT_EQ(diagonal.size(), 2u + 6u);  // (4, 5) and (6, 5) shared
  EXPECT_DOUBLE_EQ(diagonal.at({4, 5}), 2.0);
  EXPECT_DOUBLE_EQ(diagonal.at({6, 5}), 2.0);
  EXPECT_EQ(diagonal.count({5, 5}), 0u);  // a direct neighbour of both: not a diagonal one

  // Adjacent points do not overwrite each other.
  const LevelInverseDistances touching = at({{{5, 5}, 1.0}, {{5, 6}, 3.0}});
  const LevelInverseDistances out =
      dilateInverseDistances(touching, 12, 10, DilationNeighbours::kDirect);
  EXPECT_DOUBLE_EQ(out.at({5, 5}), 1.0);
  EXPECT_DOUBLE_EQ(out.at({5, 6}), 3.0);
}

// The tracker keeps its points one pixel inside the image (it samples their neighbours) and
// inside the content; so does the dilation.
TEST(ReferenceDilation, NothingIsAddedOnTheImageEdgeOrOutsideTheContent) {
  const LevelInverseDistances corner = at({{{1, 1}, 0.5}});
  EXPECT_EQ(dilateInverseDistances(corner, 12, 10, DilationNeighbours::kDiagonal),
            at({{{1, 1}, 0.5}, {{2, 2}, 0.5}}));
  EXPECT_EQ(dilateInverseDistances(corner, 12, 10, DilationNeighbours::kDirect),
            at({{{1, 1}, 0.5}, {{1, 2}, 0.5}, {{2, 1}, 0.5}}));
  const LevelInverseDistances far_corner = at({{{8, 10}, 0.5}});  // v = h − 2, u = w − 2
  EXPECT_EQ(dilateInverseDistances(far_corner, 12, 10, DilationNeighbours::kDirect),
            at({{{7, 10}, 0.5}, {{8, 9}, 0.5}, {{8, 10}, 0.5}}));

  Mask content(12, 10, 1);
  content(6, 5) = 0;  // (u, v)
  EXPECT_EQ(dilateInverseDistances(at({{{5, 5}, 0.5}}), 12, 10, DilationNeighbours::kDirect,
                                   &content),
            at({{{4, 5}, 0.5}, {{5, 4}, 0.5}, {{5, 5}, 0.5}, {{6, 5}, 0.5}}));
}

}  // namespace
}  // namespace omnidso
