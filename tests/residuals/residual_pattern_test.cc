// Residual patterns: sizes, distinct offsets, the centre pixel, DSO's exact offsets.

#include "omnidso/residuals/residual_pattern.hpp"

#include <gtest/gtest.h>

#include <set>
#include <utility>

namespace omnidso {
namespace {

template <int N>
void expectDistinctWithCentre() {
  std::set<std::pair<int, int>> seen;
  for (const PatternOffset& o : ResidualPattern<N>::kOffsets) seen.insert({o.du, o.dv});
  EXPECT_EQ(seen.size(), static_cast<size_t>(N));
  EXPECT_EQ(seen.count({0, 0}), 1u);
}

TEST(ResidualPatternTest, PatternsAreDistinctAndContainTheHostPixel) {
  expectDistinctWithCentre<1>();
  expectDistinctWithCentre<5>();
  expectDistinctWithCentre<8>();
  EXPECT_EQ(patternRadius<1>(), 0);
  EXPECT_EQ(patternRadius<5>(), 1);
  EXPECT_EQ(patternRadius<8>(), 2);
}

TEST(ResidualPatternTest, DsoPatternOffsets) {
  const std::set<std::pair<int, int>> expected = {{0, -2}, {-1, -1}, {1, -1}, {-2, 0},
                                                  {0, 0},  {2, 0},   {-1, 1}, {0, 2}};
  std::set<std::pair<int, int>> actual;
  for (const PatternOffset& o : ResidualPattern<8>::kOffsets) actual.insert({o.du, o.dv});
  EXPECT_EQ(actual, expected);
}

}  // namespace
}  // namespace omnidso
