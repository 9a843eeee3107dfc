// affineInMovedKeyframeGauge (affine_gauge.hpp): the frame's transfer from its keyframe,
// gain s and offset o = b_f − s b_r, is what the images fix, so it must not change when the
// window moves the keyframe's [a, b].
#include <gtest/gtest.h>

#include <omnidso/frontend/affine_gauge.hpp>

namespace omnidso {
namespace {

struct Transfer {
  double gain;
  double offset;
};

Transfer transfer(const Eigen::Vector2d& frame, double frame_exposure,
                  const Eigen::Vector2d& keyframe, double keyframe_exposure) {
  const double s = frame_exposure / keyframe_exposure * std::exp(frame.x() - keyframe.x());
  return {s, frame.y() - s * keyframe.y()};
}

TEST(AffineGauge, TheTransferFromTheKeyframeSurvivesTheMove) {
  // Gauges like those the uncalibrated H7 reaches without a tie on b (a to −1.9, b to 120),
  // frames brighter and darker than their keyframe, with and without exposure times.
  struct Case {
    Eigen::Vector2d frame, before, after;
    double t_frame, t_keyframe;
  };
  const Case cases[] = {
      {{-0.80, 49.3}, {-0.84, 48.0}, {-0.90, 58.4}, 1.0, 1.0},
      {{-1.20, 80.0}, {-1.00, 75.0}, {-1.85, 120.0}, 1.0, 1.0},
      {{0.10, -3.0}, {0.00, 0.0}, {0.05, 4.0}, 12.0, 8.0},
      {{0.30, 10.0}, {0.20, 10.0}, {0.20, 10.0}, 1.0, 1.0},  // not moved
  };
  for (const Case& c : cases) {
    const Eigen::Vector2d moved =
        affineInMovedKeyframeGauge(c.frame, c.t_frame, c.before, c.after, c.t_keyframe);
    const Transfer old_gauge = transfer(c.frame, c.t_frame, c.before, c.t_keyframe);
    const Transfer new_gauge = transfer(moved, c.t_frame, c.after, c.t_keyframe);
    // Each side is a handful of exp and products of numbers ≤ 1e2: rounding ≲ 1e-13.
    EXPECT_NEAR(new_gauge.gain, old_gauge.gain, 1e-12 * old_gauge.gain);
    EXPECT_NEAR(new_gauge.offset, old_gauge.offset, 1e-11);
  }
}

TEST(AffineGauge, TheOffsetsCorrectionIsScaledByTheGain) {
  // A frame 1.5 times as bright as its keyframe (exposure 1.5, same a): the keyframe's offset
  // moving by 10 moves the frame's by 15. Adding the keyframe's change unscaled would leave the
  // frame's transfer offset wrong by (1 − s) · 10 = −5 intensity units on every pixel.
  const Eigen::Vector2d moved = affineInMovedKeyframeGauge(
      Eigen::Vector2d(-0.5, 30.0), 1.5, Eigen::Vector2d(-0.5, 20.0), Eigen::Vector2d(-0.7, 30.0),
      1.0);
  EXPECT_NEAR(moved.x(), -0.7, 1e-15);
  EXPECT_NEAR(moved.y(), 45.0, 1e-12);
}

}  // namespace
}  // namespace omnidso
