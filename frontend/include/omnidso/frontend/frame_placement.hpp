#pragma once
// A tracked frame placed in the window's current estimate by its tracking reference.
//
// Tracking measures a frame f against one keyframe R: its pose relative to R, T_f_R. When a
// window solve moves R before the frame is mapped (T_world_R → T_world_R'), the frame in the
// new estimate is
//   T_world_f' = T_world_R' · T_f_R⁻¹,
// as DSO places every frame at mapping time (camToWorld = trackingRef→camToWorld ·
// camToTrackingRef). The real-time mode maps a frame tracked while the mapper was solving only
// after that solve; with its world pose from before it, the epipolar search formed the frame's
// pose relative to each host from hosts in the new estimate and a frame in the old one (the
// uncalibrated H7 lost its scale in real-time runs: docs/performance.md, "The real-time mode
// places a frame by its reference"). The affine [a, b] stays as tracked, as in DSO: carried
// into the reference's moved brightness gauge (affine_gauge.hpp) it made one sequence's
// real-time runs 4× less accurate and did nothing for H7 (same section).
// With R unmoved the result is the tracker's own T_world_R · T_f_R⁻¹, bit for bit: the
// deterministic mode maps every frame before the window changes.
//
// The constant-velocity guess. The next frame is tracked from the motion between the last two
// frames, T_last⁻¹ · T_prev; both must be taken in one estimate. After a keyframe's solve the
// last frame is the keyframe, at the window's new pose of it; the previous frame must be taken
// in that estimate too (poseInCurrentEstimate), or the guess carries whatever the solve moved
// in between. In fast turns of a narrow view, where every frame becomes a keyframe and each
// solve moves the previous one, the first frame tracked after a keyframe was 8–21 % short with
// rotation errors of 0.1–0.3°, and the new points triangulated from it came in near
// (docs/performance.md, "The constant-velocity guess in one estimate").

#include <omnidso/core/se3.hpp>
#include <omnidso/frontend/odometry.hpp>

namespace omnidso {

inline SE3d placeByReference(const SE3d& T_world_reference, const SE3d& T_frame_reference) {
  return T_world_reference * T_frame_reference.inverse();
}

// A tracked frame in the current estimate: a keyframe at its own pose, any other frame placed
// by its reference. `keyframe_pose(id)`: the current pose of keyframe `id` (the window's while
// it is in the window).
template <class KeyframePose>
SE3d poseInCurrentEstimate(const FrameRecord& frame, const KeyframePose& keyframe_pose) {
  if (frame.is_keyframe) return keyframe_pose(frame.index);
  return placeByReference(keyframe_pose(frame.reference_keyframe), frame.T_frame_ref);
}

}  // namespace omnidso
