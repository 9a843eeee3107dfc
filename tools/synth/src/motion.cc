// Camera trajectories for the renderer; the models are described in motion.hpp.
#include <omnidso/synth/motion.hpp>

#include <algorithm>
#include <cmath>

#include <omnidso/core/error.hpp>
#include <omnidso/synth/random.hpp>

namespace omnidso::synth {
namespace {

double quinticStep(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * s * (s * (6.0 * s - 15.0) + 10.0);
}

Eigen::Matrix3d rotationX(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d rotationZ(double angle) {
  return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

Eigen::Matrix3d levelCameraRotation(double yaw) {
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  Eigen::Matrix3d r;
  r.col(0) << s, -c, 0.0;
  r.col(1) << 0.0, 0.0, -1.0;
  r.col(2) << c, s, 0.0;
  return r;
}

HandheldMotion::HandheldMotion(const AlignedBox& free_space, const HandheldMotionConfig& config,
                               std::uint64_t seed)
    : free_space_(free_space) {
  SeededRandom random(counterHash(seed, 0x40710));
  // Waves whose amplitudes sum to `total` (so |Σ| ≤ total).
  auto makeWaves = [&random](int count, double total, double min_hz, double max_hz) {
    std::vector<Wave> waves(static_cast<size_t>(count));
    double sum = 0.0;
    for (Wave& wave : waves) {
      wave.amplitude = random.uniform(0.3, 1.0);
      wave.frequency_hz = random.uniform(min_hz, max_hz);
      wave.phase = random.uniform(0.0, 2.0 * M_PI);
      sum += wave.amplitude;
    }
    for (Wave& wave : waves) wave.amplitude *= total / sum;
    return waves;
  };
  for (auto& axis : position_) axis = makeWaves(3, 1.0, 0.03, 0.25);
  yaw_ = makeWaves(3, 0.8, 0.02, 0.1);
  yaw_.push_back({random.uniform(-M_PI, M_PI), 0.0, M_PI / 2});  // constant initial heading
  pitch_ = makeWaves(3, config.pitch_amplitude, 0.05, 0.3);
  roll_ = makeWaves(3, config.roll_amplitude, 0.05, 0.3);
  tremor_ = makeWaves(2, config.tremor_amplitude, 5.0, 8.0);
  for (double start = random.uniform(1.0, 3.0); start < config.duration_s;) {
    Burst burst;
    burst.angle = random.uniform(0.6, 2.0) * (random.uniform() < 0.5 ? -1.0 : 1.0);
    // Peak rate of the quintic step is 1.875·A/d; choose d so it stays ≤ max_burst_rate.
    burst.duration_s = std::max(0.35, 1.875 * std::abs(burst.angle) / config.max_burst_rate);
    burst.start_s = start;
    bursts_.push_back(burst);
    start += burst.duration_s + random.uniform(1.5, 4.0);
  }
}

double HandheldMotion::evaluate(const std::vector<Wave>& waves, double t) {
  double sum = 0.0;
  for (const Wave& wave : waves) {
    sum += wave.amplitude * std::sin(2.0 * M_PI * wave.frequency_hz * t + wave.phase);
  }
  return sum;
}

SE3d HandheldMotion::poseAt(double t) const {
  Eigen::Vector3d position;
  const Eigen::Vector3d centre = free_space_.centre();
  const Eigen::Vector3d half = 0.5 * free_space_.size();
  for (int a = 0; a < 3; ++a) position[a] = centre[a] + half[a] * evaluate(position_[a], t);
  double yaw = evaluate(yaw_, t) + evaluate(tremor_, t);
  for (const Burst& burst : bursts_) {
    yaw += burst.angle * quinticStep((t - burst.start_s) / burst.duration_s);
  }
  const double pitch = evaluate(pitch_, t) + evaluate(tremor_, t + 0.37);
  const double roll = evaluate(roll_, t);
  const Eigen::Matrix3d rotation = levelCameraRotation(yaw) * rotationX(pitch) * rotationZ(roll);
  return SE3d(rotation, position);
}

Eigen::Matrix3d bodyToCameraRotation(const Trajectory& body_trajectory) {
  Eigen::Vector3d up_in_body = Eigen::Vector3d::Zero();
  for (const StampedPose& pose : body_trajectory) {
    up_in_body += pose.pose.rotation().conjugate() * Eigen::Vector3d::UnitZ();
  }
  up_in_body.normalize();
  const Eigen::Vector3d down = -up_in_body;
  // Forward: body z if it is near horizontal (|up component| < 0.3, i.e. within ~17°),
  // else body x, else body y; failing all, the most horizontal axis.
  int best_axis = -1;
  for (const int a : {2, 0, 1}) {
    if (best_axis < 0 && std::abs(up_in_body[a]) < 0.3) best_axis = a;
  }
  if (best_axis < 0) {
    best_axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (std::abs(up_in_body[a]) < std::abs(up_in_body[best_axis])) best_axis = a;
    }
  }
  Eigen::Vector3d forward = Eigen::Vector3d::Unit(best_axis);
  forward = (forward - forward.dot(down) * down).normalized();
  Eigen::Matrix3d r_body_cam;
  r_body_cam.col(0) = down.cross(forward);
  r_body_cam.col(1) = down;
  r_body_cam.col(2) = forward;
  return r_body_cam;
}

Trajectory recordedCameraTrajectory(const Trajectory& body_trajectory, const std::string& source,
                                    const AlignedBox& free_space, double fps, int max_frames,
                                    double margin_m) {
  if (body_trajectory.size() < 2) {
    throw fileError(source, "a trajectory needs at least two poses to be resampled");
  }
  const SE3d body_to_camera(bodyToCameraRotation(body_trajectory), Eigen::Vector3d::Zero());
  const double t0 = body_trajectory.front().timestamp;
  const double t_end = body_trajectory.back().timestamp;
  const int available = static_cast<int>(std::floor((t_end - t0) * fps)) + 1;
  const int count = std::min(max_frames, available);
  Trajectory cameras;
  size_t segment = 0;
  for (int k = 0; k < count; ++k) {
    const double t = t0 + k / fps;
    while (segment + 2 < body_trajectory.size() && body_trajectory[segment + 1].timestamp < t) {
      ++segment;
    }
    const StampedPose& a = body_trajectory[segment];
    const StampedPose& b = body_trajectory[segment + 1];
    const double s = std::clamp((t - a.timestamp) / (b.timestamp - a.timestamp), 0.0, 1.0);
    cameras.push_back({t, interpolate(a.pose, b.pose, s) * body_to_camera});
  }
  // Place the path: centre its bounding box in the free space, shrink it if needed.
  Eigen::Vector3d lo = cameras.front().pose.translation();
  Eigen::Vector3d hi = lo;
  for (const StampedPose& pose : cameras) {
    lo = lo.cwiseMin(pose.pose.translation());
    hi = hi.cwiseMax(pose.pose.translation());
  }
  const Eigen::Vector3d room = free_space.size() - Eigen::Vector3d::Constant(2.0 * margin_m);
  const Eigen::Vector3d extent = hi - lo;
  double scale = 1.0;
  for (int a = 0; a < 3; ++a) {
    if (extent[a] > 0) scale = std::min(scale, room[a] / extent[a]);
  }
  const Eigen::Vector3d path_centre = 0.5 * (lo + hi);
  for (StampedPose& pose : cameras) {
    pose.pose.translation() =
        free_space.centre() + scale * (pose.pose.translation() - path_centre);
  }
  return cameras;
}

}  // namespace omnidso::synth
