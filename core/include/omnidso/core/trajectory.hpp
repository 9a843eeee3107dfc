#pragma once
// A trajectory: camera (or body) poses T_world_cam with their timestamps in seconds,
// in increasing time order. Readers guarantee strictly increasing timestamps.

#include <Eigen/Core>
#include <omnidso/core/se3.hpp>
#include <vector>

namespace omnidso {

struct StampedPose {
  double timestamp;  // seconds; for KITTI files (no timestamps) the line index
  SE3d pose;         // T_world_cam
};

using Trajectory = std::vector<StampedPose>;

// The translations of all poses as the columns of a 3×N matrix (the camera centres).
inline Eigen::Matrix3Xd positions(const Trajectory& trajectory) {
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(trajectory.size()));
  for (size_t i = 0; i < trajectory.size(); ++i) {
    out.col(static_cast<Eigen::Index>(i)) = trajectory[i].pose.translation();
  }
  return out;
}

}  // namespace omnidso
