#pragma once
// A tracked frame placed in the window's current estimate by its tracking reference.
//
// Tracking measures a frame f against one keyframe R: its pose relative to R, T_f_R, and its
// affine [a_f, b_f] in the brightness gauge R had when it was published, [a_R, b_R]. The
// images fix that relative pose and the brightness transfer from R (affine_gauge.hpp), not
// the world pose or the affine themselves. When a window solve moves R before the frame is
// mapped (T_world_R → T_world_R', [a_R, b_R] → [a_R', b_R']), the frame in the new estimate is
//   T_world_f' = T_world_R' · T_f_R⁻¹,
//   [a_f', b_f'] = affineInMovedKeyframeGauge([a_f, b_f], t_f, [a_R, b_R], [a_R', b_R'], t_R).
// The real-time mode maps a frame tracked while the mapper was solving only after that solve;
// with its world pose and affine from before it, the epipolar search met hosts in the new
// estimate with a pose and a brightness transfer from the old one (the uncalibrated H7 lost its
// scale in two real-time runs of three: docs/performance.md, "The real-time mode places a
// frame by its reference"). DSO places frames the same way at mapping time (a frame's
// camToWorld = its tracking reference's camToWorld · camToTrackingRef).
// With R unmoved the result is the tracker's own T_world_R · T_f_R⁻¹ and [a_f, b_f], bit for
// bit: the deterministic mode maps every frame before the window changes.

#include <Eigen/Core>
#include <omnidso/core/se3.hpp>
#include <omnidso/frontend/affine_gauge.hpp>

namespace omnidso {

// What tracking measured.
struct TrackedFrame {
  SE3d T_frame_reference;
  Eigen::Vector2d affine = Eigen::Vector2d::Zero();  // in the reference's gauge when tracked
  double exposure = 1.0;
  Eigen::Vector2d reference_affine = Eigen::Vector2d::Zero();  // the reference's, when tracked
};

// The reference keyframe as the window estimates it now.
struct ReferenceEstimate {
  SE3d T_world_reference;
  Eigen::Vector2d affine = Eigen::Vector2d::Zero();
  double exposure = 1.0;
};

struct FramePlacement {
  SE3d T_world_frame;
  Eigen::Vector2d affine = Eigen::Vector2d::Zero();
};

inline FramePlacement placeByReference(const TrackedFrame& frame,
                                       const ReferenceEstimate& reference) {
  return {reference.T_world_reference * frame.T_frame_reference.inverse(),
          affineInMovedKeyframeGauge(frame.affine, frame.exposure, frame.reference_affine,
                                     reference.affine, reference.exposure)};
}

}  // namespace omnidso
