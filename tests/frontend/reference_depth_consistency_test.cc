// The tracking reference's neighbour check (reference_depth_consistency.hpp): on a smooth
// surface it keeps every point and drops the isolated wrong ones; it keeps a foreground
// object's inside; its grid search finds the same neighbours as a brute-force one; and it
// refuses meaningless settings. Off by default, it changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/reference_depth_consistency.hpp>
#include <random>
#include <set>
#include <vector>

#include "support/error_message.hpp"

namespace omnidso {
namespace {

const ReferenceDepthConsistencyOptions kCheck{8, 0.1};  // K = 8, τ = 0.1

// Points on a grid of `step` pixels, the inverse distance from fn(u, v).
template <typename Fn>
std::vector<TrackingReferencePoint> gridPoints(int cols, int rows, double step, Fn fn) {
  std::vector<TrackingReferencePoint> points;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d pixel(10.0 + step * c, 10.0 + step * r);
      points.push_back({pixel, fn(pixel.x(), pixel.y())});
    }
  return points;
}

bool samePoint(const TrackingReferencePoint& a, const TrackingReferencePoint& b) {
  return a.pixel == b.pixel && a.inverse_distance == b.inverse_distance;
}

// A slanted plane: ln d changes by at most 0.6 % between grid neighbours (14 px apart at
// most), far below τ = 0.1. Every tenth point off by ±20 % (|ln| ≥ 0.18 > τ), none of them
// neighbours of another, and every seventh by ±3 % (< τ) — the wrong ones and only they go.
TEST(ReferenceDepthConsistency, KeepsASmoothSurfaceAndDropsIsolatedWrongPoints) {
  std::vector<TrackingReferencePoint> points =
      gridPoints(30, 30, 10.0, [](double u, double v) { return 0.5 + 0.0004 * u + 0.0002 * v; });
  std::set<size_t> wrong;
  for (size_t i = 0; i < points.size(); ++i) {
    const size_t r = i / 30, c = i % 30;
    if (r % 3 == 1 && c % 4 == 1) {  // isolated: two free grid steps between any two
      points[i].inverse_distance *= (wrong.size() % 2 == 0) ? 1.2 : 1.0 / 1.2;
      wrong.insert(i);
    } else if (i % 7 == 0) {
      points[i].inverse_distance *= (i % 2 == 0) ? 1.03 : 0.97;
    }
  }
  ASSERT_GT(wrong.size(), 50u);
  const std::vector<TrackingReferencePoint> kept = keepConsistentDepths(points, kCheck);
  ASSERT_EQ(kept.size(), points.size() - wrong.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (wrong.count(i)) continue;
    EXPECT_TRUE(samePoint(kept[k++], points[i])) << "point " << i << " lost or out of order";
  }
}

// A 5 × 5 block of points at four times the background's inverse distance (an object in
// front of a wall): the block's inner 3 × 3 have all eight nearest neighbours inside the
// block and stay, as does every background point two grid steps or more from the block.
TEST(ReferenceDepthConsistency, KeepsTheInsideOfAForegroundObject) {
  const auto in_block = [](int c, int r) { return c >= 10 && c < 15 && r >= 10 && r < 15; };
  std::vector<TrackingReferencePoint> points;
  for (int r = 0; r < 25; ++r)
    for (int c = 0; c < 25; ++c)
      points.push_back({Eigen::Vector2d(10.0 * c, 10.0 * r), in_block(c, r) ? 1.0 : 0.25});
  const std::vector<TrackingReferencePoint> kept = keepConsistentDepths(points, kCheck);
  const auto isKept = [&kept](const TrackingReferencePoint& p) {
    return std::any_of(kept.begin(), kept.end(),
                       [&p](const TrackingReferencePoint& q) { return samePoint(p, q); });
  };
  for (int r = 0; r < 25; ++r)
    for (int c = 0; c < 25; ++c) {
      const TrackingReferencePoint& p = points[r * 25 + c];
      const bool inner = c >= 11 && c < 14 && r >= 11 && r < 14;
      const bool far_background = c <= 8 || c >= 16 || r <= 8 || r >= 16;
      if (inner || far_background) {
        EXPECT_TRUE(isKept(p)) << "column " << c << " row " << r;
      }
    }
}

// The grid's ring search against sorting every distance: random pixels (no equal distances)
// in clusters and alone, random inverse distances, several K and τ.
TEST(ReferenceDepthConsistency, AgreesWithABruteForceNeighbourSearch) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pixel(0.0, 640.0), cluster(-6.0, 6.0), log_d(-1.0, 1.0);
  std::vector<TrackingReferencePoint> points;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d centre(pixel(rng), 0.75 * pixel(rng));
    const int members = (i % 5 == 0) ? 8 : 1;
    for (int m = 0; m < members; ++m)
      points.push_back({centre + Eigen::Vector2d(cluster(rng), cluster(rng)),
                        std::exp(0.15 * log_d(rng))});
  }
  for (const int k : {1, 4, 8, 15})
    for (const double tau : {0.03, 0.1}) {
      std::vector<TrackingReferencePoint> expected;
      for (size_t i = 0; i < points.size(); ++i) {
        std::vector<std::pair<double, double>> by_distance;  // (squared distance, ln d)
        for (size_t j = 0; j < points.size(); ++j) {
          if (j == i) continue;
          by_distance.push_back({(points[j].pixel - points[i].pixel).squaredNorm(),
                                 std::log(points[j].inverse_distance)});
        }
        std::sort(by_distance.begin(), by_distance.end());
        std::vector<double> values;
        for (int n = 0; n < k; ++n) values.push_back(by_distance[n].second);
        std::sort(values.begin(), values.end());
        const double median =
            k % 2 ? values[k / 2] : 0.5 * (values[k / 2 - 1] + values[k / 2]);
        if (std::abs(std::log(points[i].inverse_distance) - median) <= tau)
          expected.push_back(points[i]);
      }
      const std::vector<TrackingReferencePoint> kept = keepConsistentDepths(points, {k, tau});
      SCOPED_TRACE(testing::Message() << "K " << k << " tau " << tau);
      ASSERT_EQ(kept.size(), expected.size());
      ASSERT_LT(kept.size(), points.size());  // the check had something to drop
      for (size_t i = 0; i < kept.size(); ++i) EXPECT_TRUE(samePoint(kept[i], expected[i]));
    }
}

TEST(ReferenceDepthConsistency, KeepsEveryPointWhenOffOrTooFewToJudge) {
  std::vector<TrackingReferencePoint> points =
      gridPoints(3, 3, 10.0, [](double u, double) { return u < 20 ? 1.0 : 3.0; });
  EXPECT_EQ(keepConsistentDepths(points, {0, 0.1}).size(), points.size());  // K = 0: off
  EXPECT_EQ(keepConsistentDepths(points, {9, 0.1}).size(), points.size());  // 9 < K + 1
  EXPECT_LT(keepConsistentDepths(points, {4, 0.1}).size(), points.size());  // judged
  EXPECT_TRUE(keepConsistentDepths({}, kCheck).empty());
  EXPECT_EQ(keepConsistentDepths(points, {}).size(), points.size());  // off by default
}

TEST(ReferenceDepthConsistency, RefusesMeaninglessSettingsNamingThem) {
  const std::vector<TrackingReferencePoint> points =
      gridPoints(4, 4, 10.0, [](double, double) { return 1.0; });
  EXPECT_NE(test::errorMessage([&] { keepConsistentDepths(points, {-1, 0.1}); })
                .find("reference_depths.neighbours"),
            std::string::npos);
  for (const double tau : {0.0, -0.1, std::nan(""), HUGE_VAL})
    EXPECT_NE(test::errorMessage([&] { keepConsistentDepths(points, {8, tau}); })
                  .find("reference_depths.max_log_deviation"),
              std::string::npos)
        << tau;
  std::vector<TrackingReferencePoint> negative = points;
  negative[3].inverse_distance = -1.0;
  EXPECT_NE(test::errorMessage([&] { keepConsistentDepths(negative, kCheck); }).find("not positive"),
            std::string::npos);
}

}  // namespace
}  // namespace omnidso
