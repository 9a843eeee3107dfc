// Frame-management policy (paper Sec. V-C): hand-built windows in which each rule decides.
#include <gtest/gtest.h>

#include <omnidso/backend/keyframe_marginalization_policy.hpp>

namespace omnidso {
namespace {

KeyframeSummary keyframe(int id, double x, int points = 100, int visible = 100) {
  KeyframeSummary kf;
  kf.id = id;
  kf.T_world_cam = SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, 0, 0));
  kf.num_points = points;
  kf.num_points_visible_in_newest = visible;
  return kf;
}

KeyframeMarginalizationOptions withMax(int n) {
  KeyframeMarginalizationOptions o;
  o.max_keyframes = n;
  return o;
}

TEST(KeyframeMarginalizationPolicy, FullWindowBelowLimitKeepsEverything) {
  const std::vector<KeyframeSummary> w = {keyframe(0, 0), keyframe(1, 1), keyframe(2, 2)};
  EXPECT_TRUE(selectKeyframesToMarginalize(w, withMax(3)).empty());
}

TEST(KeyframeMarginalizationPolicy, FivePercentRuleMarginalizesPoorlyVisibleKeyframe) {
  // Keyframe 1 sees 4 of 100 points in the newest (4% < 5%); keyframe 2 sees exactly 5%.
  const std::vector<KeyframeSummary> w = {keyframe(0, 0), keyframe(1, 1, 100, 4),
                                          keyframe(2, 2, 100, 5), keyframe(3, 3), keyframe(4, 4)};
  EXPECT_EQ(selectKeyframesToMarginalize(w, withMax(7)), std::vector<int>({1}));
}

TEST(KeyframeMarginalizationPolicy, TwoNewestAreNeverMarginalized) {
  // The two newest see nothing of their own points in I_1 and the window is over N_f,
  // yet neither may go: rule b skips them and rule c picks among the older ones only.
  const std::vector<KeyframeSummary> w = {keyframe(0, 0), keyframe(1, 0.1), keyframe(2, 5, 100, 0),
                                          keyframe(3, 5.1, 100, 0)};
  const std::vector<int> chosen = selectKeyframesToMarginalize(w, withMax(3));
  ASSERT_EQ(chosen.size(), 1u);
  EXPECT_NE(chosen[0], 2);
  EXPECT_NE(chosen[0], 3);
}

TEST(KeyframeMarginalizationPolicy, DistanceScoreMarginalizesRedundantFarKeyframe) {
  // Old keyframes 0 and 1 are close to each other and far from the newest (x = 10);
  // keyframe 2 stands alone near the newest. Scores (ε negligible):
  //   s0 = √10 (1/0.1 + 1/8) ≈ 32.02, s1 = √9.9 (1/0.1 + 1/7.9) ≈ 31.86, s2 = √2 (1/8 + 1/7.9) ≈ 0.36
  // so keyframe 0 — redundant with 1 and the farthest — leaves.
  const std::vector<KeyframeSummary> w = {keyframe(0, 0), keyframe(1, 0.1), keyframe(2, 8),
                                          keyframe(3, 9.5), keyframe(4, 10)};
  EXPECT_EQ(selectKeyframesToMarginalize(w, withMax(4)), std::vector<int>({0}));
  const std::vector<size_t> candidates = {0, 1, 2};
  EXPECT_NEAR(keyframeDistanceScore(w, 0, candidates, 1e-5),
              std::sqrt(10.0) * (1 / (0.1 + 1e-5) + 1 / (8 + 1e-5)), 1e-9);
}

TEST(KeyframeMarginalizationPolicy, FivePercentRuleCanMakeDistanceRuleUnnecessary) {
  // Over the limit by one, but rule b already removes a keyframe: no second removal.
  const std::vector<KeyframeSummary> w = {keyframe(0, 0), keyframe(1, 1, 50, 1), keyframe(2, 2),
                                          keyframe(3, 3), keyframe(4, 4)};
  EXPECT_EQ(selectKeyframesToMarginalize(w, withMax(4)), std::vector<int>({1}));
}

TEST(KeyframeMarginalizationPolicy, KeyframeWithoutPointsIsLeftToDistanceRule) {
  const std::vector<KeyframeSummary> w = {keyframe(0, 0, 0, 0), keyframe(1, 1), keyframe(2, 2)};
  EXPECT_TRUE(selectKeyframesToMarginalize(w, withMax(7)).empty());
}

}  // namespace
}  // namespace omnidso
