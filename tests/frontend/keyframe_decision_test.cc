// The keyframe decision (DSO's weighted flow, brightness and error-growth criteria).
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/frontend/keyframe_decision.hpp>

namespace omnidso {
namespace {

TrackingResult tracked(double flow_t, double flow_rt, double rmse) {
  TrackingResult t;
  t.ok = true;
  t.flow_t = flow_t;
  t.flow_rt = flow_rt;
  t.rmse = rmse;
  return t;
}

TEST(KeyframeDecision, TranslationalFlowThresholdScalesWithImageSize) {
  const KeyframeDecisionOptions o;
  // 640×480: s = 0.04 f_t, so 24 px stays below 1 and 26 px crosses it.
  EXPECT_FALSE(decideKeyframe(tracked(24, 0, 1), 1.0, 1.0, 640, 480, o).make_keyframe);
  EXPECT_TRUE(decideKeyframe(tracked(26, 0, 1), 1.0, 1.0, 640, 480, o).make_keyframe);
  // 480×480: the same score needs 25·960/1120 ≈ 21.4 px.
  EXPECT_NEAR(decideKeyframe(tracked(25.0 * 960 / 1120, 0, 1), 1.0, 1.0, 480, 480, o).score,
              1.0, 1e-12);
}

TEST(KeyframeDecision, RotationAloneCountsAtHalfWeight) {
  const KeyframeDecisionOptions o;
  // Pure rotation: f_t = 0; the full-motion flow needs 50 px on 640×480.
  EXPECT_FALSE(decideKeyframe(tracked(0, 49, 1), 1.0, 1.0, 640, 480, o).make_keyframe);
  EXPECT_TRUE(decideKeyframe(tracked(0, 51, 1), 1.0, 1.0, 640, 480, o).make_keyframe);
}

TEST(KeyframeDecision, BrightnessChangeAloneTriggers) {
  const KeyframeDecisionOptions o;
  // 2 |log r| > 1 ⇔ r > e^{1/2} ≈ 1.6487 or r < e^{-1/2}.
  EXPECT_FALSE(decideKeyframe(tracked(0, 0, 1), 1.6, 1.0, 640, 480, o).make_keyframe);
  EXPECT_TRUE(decideKeyframe(tracked(0, 0, 1), 1.7, 1.0, 640, 480, o).make_keyframe);
  EXPECT_TRUE(decideKeyframe(tracked(0, 0, 1), 1.0 / 1.7, 1.0, 640, 480, o).make_keyframe);
}

TEST(KeyframeDecision, ErrorGrowthTriggers) {
  const KeyframeDecisionOptions o;
  const KeyframeDecision grew = decideKeyframe(tracked(0, 0, 2.1), 1.0, 1.0, 640, 480, o);
  EXPECT_TRUE(grew.rmse_grew);
  EXPECT_TRUE(grew.make_keyframe);
  EXPECT_FALSE(decideKeyframe(tracked(0, 0, 1.9), 1.0, 1.0, 640, 480, o).make_keyframe);
}

}  // namespace
}  // namespace omnidso
