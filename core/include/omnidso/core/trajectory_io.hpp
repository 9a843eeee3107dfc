#pragma once
// Reading and writing trajectory files. Every reader throws omnidso::Error naming the file
// and line on malformed input: wrong column count, non-numeric or non-finite fields,
// quaternions whose norm is off by more than 1e-3 (smaller errors come from printing with
// few digits and are normalised away), non-increasing timestamps, and files with no pose.
//
// Formats (blank lines and lines starting with '#' are skipped; fields are separated by
// white space and/or commas):
//   kTum:   "t tx ty tz qx qy qz qw"            — 8 fields, T_world_cam, t in seconds
//   kKitti: "r00 r01 r02 tx r10 ... r22 tz"      — 12 fields, the 3×4 matrix row-major;
//           no timestamps, so the timestamp of the k-th pose is k (0, 1, 2, ...)
//   kEuroc: "t_ns, px, py, pz, qw, qx, qy, qz, ..." — EuRoC ground-truth CSV, at least 8
//           fields (velocities and biases after them are ignored), t in nanoseconds

#include <omnidso/core/trajectory.hpp>
#include <string>

namespace omnidso {

enum class TrajectoryFormat { kTum, kKitti, kEuroc };

// "tum", "kitti", "euroc" → format; anything else throws Error.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format);
inline Trajectory readTrajectoryTum(const std::string& path) {
  return readTrajectory(path, TrajectoryFormat::kTum);
}

// TUM format with a header comment. Timestamps print with 9 decimals (nanoseconds) when
// that reproduces the double exactly, else with 17 significant digits; pose numbers print
// with 17 significant digits, so that reading the file back gives bit-identical values.
void writeTrajectoryTum(const std::string& path, const Trajectory& trajectory);

}  // namespace omnidso
