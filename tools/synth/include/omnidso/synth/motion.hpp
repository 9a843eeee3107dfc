#pragma once
// Camera trajectories for the renderer, all T_world_cam (camera x right, y down, z forward;
// world z up, scene.hpp):
// (a) HandheldMotion: procedural hand-held motion, a continuous function of time, so that
//     sub-frame poses (motion blur) come for free. Position: a sum of sinusoids per axis
//     with random frequencies (0.03–0.25 Hz) and phases whose weights sum to one, so the
//     path never leaves the free space. Rotation: the camera looks horizontally at yaw ψ,
//     tilted by pitch θ (about camera x) and roll φ (about camera z):
//       R = R_level(ψ) · R_x(θ) · R_z(φ),
//     ψ = slow wander + bursts: fast turns of angle A over d seconds with the quintic
//     smoothstep 6s⁵ − 15s⁴ + 10s³ (peak rate 1.875 A/d, kept below max_burst_rate), every
//     1.5–4 s, plus a small hand tremor (5–8 Hz).
// (b) A recorded trajectory (TUM format, body/IMU poses) turned into camera poses by a
//     fixed body→camera rotation, resampled to the frame rate and placed in the free space.

#include <cstdint>
#include <string>
#include <vector>

#include <omnidso/core/se3.hpp>
#include <omnidso/core/trajectory.hpp>
#include <omnidso/synth/scene.hpp>

namespace omnidso::synth {

struct HandheldMotionConfig {
  double duration_s = 30.0;       // bursts are generated up to this time
  double max_burst_rate = 2.5;    // rad/s, peak yaw rate of a fast turn
  double pitch_amplitude = 0.3;   // rad
  double roll_amplitude = 0.12;   // rad
  double tremor_amplitude = 0.004;  // rad
};

class HandheldMotion {
 public:
  HandheldMotion(const AlignedBox& free_space, const HandheldMotionConfig& config,
                 std::uint64_t seed);
  SE3d poseAt(double t) const;  // T_world_cam

 private:
  struct Wave {
    double amplitude, frequency_hz, phase;
  };
  struct Burst {
    double start_s, duration_s, angle;
  };
  static double evaluate(const std::vector<Wave>& waves, double t);

  AlignedBox free_space_;
  std::vector<Wave> position_[3];  // weights sum to 1 per axis
  std::vector<Wave> yaw_, pitch_, roll_, tremor_;
  std::vector<Burst> bursts_;
};

// The rotation of a camera looking horizontally along (cos ψ, sin ψ, 0) in a z-up world:
// columns are the camera axes x = (sin ψ, −cos ψ, 0), y = (0, 0, −1), z = (cos ψ, sin ψ, 0).
Eigen::Matrix3d levelCameraRotation(double yaw);

// The fixed body→camera rotation R_body_cam for a recorded body trajectory in a z-up
// world: camera y is the body's mean "down" direction (−mean of R_world_bodyᵀ e_z); camera z
// is body +z if that is near horizontal (|up component| < 0.3), else body +x, else +y (else
// the most horizontal of them), orthogonalised to y; x = y × z. For EuRoC (IMU x up) this is
// the real cam0 orientation (looking along body z); TUM VI (IMU z up) looks along body x.
Eigen::Matrix3d bodyToCameraRotation(const Trajectory& body_trajectory);

// Camera poses T_world_cam = T_world_body · (R_body_cam, 0) of a recorded trajectory,
// sampled at t₀ + k/fps (geodesic SE(3) interpolation between neighbours) for
// k < min(max_frames, frames within the recording), then placed in the free space: the
// camera centres' bounding box is centred in it and scaled uniformly by
// s = min(1, (free extent − 2·margin) / path extent) per axis, so the path keeps the margin
// from the free space's faces. Throws omnidso::Error (naming the file) for fewer than two
// poses.
Trajectory recordedCameraTrajectory(const Trajectory& body_trajectory, const std::string& source,
                                    const AlignedBox& free_space, double fps, int max_frames,
                                    double margin_m = 0.1);

}  // namespace omnidso::synth
