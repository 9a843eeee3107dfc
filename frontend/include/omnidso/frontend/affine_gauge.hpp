#pragma once
// A frame's brightness gain over a reference, and its affine brightness carried into a
// keyframe's moved gauge.
//
// The brightness model (paper eq. 5): frame k sees I_k = t_k e^{a_k} L + b_k, with L the
// scene's radiance in the window's gauge. Without exposure times the window's [a, b] are free,
// and a solve may move a keyframe's [a_r, b_r] to [a_r', b_r']: a new gauge for everything
// measured against that keyframe. A frame the tracker aligned to that keyframe before the move
// still sees the same image, so what must survive the move is its transfer from the keyframe,
//   s = t_f e^{a_f} / (t_r e^{a_r}),   o = b_f − s b_r        (I_f = s I_r + o),
// and in the new gauge (s and o unchanged) that is
//   a_f' = a_f + (a_r' − a_r),         b_f' = o + s b_r' = b_f + s (b_r' − b_r).
// The offset's correction is scaled by the gain s: a frame s times as bright as its keyframe
// sees the keyframe's offset change s times. The real-time mode's tracking thread applies this
// when it adopts a keyframe the mapper has solved (odometry_tracking.cc,
// adoptPublishedReference); the deterministic mode continues from the keyframe itself.

#include <Eigen/Core>
#include <cmath>

namespace omnidso {

// The gain s = t_f e^{a_f} / (t_r e^{a_r}) of a frame's brightness over a reference's (eq. 5).
inline double brightnessGain(double frame_exposure, double frame_a, double reference_exposure,
                             double reference_a) {
  return frame_exposure / reference_exposure * std::exp(frame_a - reference_a);
}

inline Eigen::Vector2d affineInMovedKeyframeGauge(const Eigen::Vector2d& frame_affine,
                                                  double frame_exposure,
                                                  const Eigen::Vector2d& keyframe_before,
                                                  const Eigen::Vector2d& keyframe_after,
                                                  double keyframe_exposure) {
  const double s = brightnessGain(frame_exposure, frame_affine.x(), keyframe_exposure,
                                  keyframe_before.x());
  return {frame_affine.x() + (keyframe_after.x() - keyframe_before.x()),
          frame_affine.y() + s * (keyframe_after.y() - keyframe_before.y())};
}

}  // namespace omnidso
