#pragma once
// Reading and writing trajectory files. Every reader throws omnidso::Error naming the file
// and line on what would give wrong numbers: wrong column count, non-numeric or non-finite
// fields, quaternions whose norm is off by more than 1e-3 (smaller errors come from printing
// with few digits and are normalised away), and files with no pose.
//
// Tolerated, as the field's real files need (docs/architecture.md, "What the readers
// accept"): a repeated timestamp keeps its first pose and drops the later ones (motion-capture
// exports, e.g. TUM RGB-D fr2/desk line 10863; evo's nearest-stamp association also takes the
// first of equal stamps); lines out of time order are sorted (stable). Both are reported
// as warnings in the result, or refused with TimestampPolicy::kStrict. Also accepted: a
// UTF-8 byte-order mark, CRLF line ends, scientific notation, a leading '+'.
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
#include <vector>

namespace omnidso {

enum class TrajectoryFormat { kTum, kKitti, kEuroc };

// "tum", "kitti", "euroc" → format; anything else throws Error.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);

// kTolerant: repeated timestamps dropped (first kept) and unsorted lines sorted, each with a
// warning; kStrict: either is an error naming the line (the readers' behaviour before
// tolerance, for a user who wants to know their file is clean).
enum class TimestampPolicy { kTolerant, kStrict };

struct TrajectoryFile {
  Trajectory poses;                   // strictly increasing timestamps
  std::vector<std::string> warnings;  // "PATH: ..." — what was repaired, for the caller to show
  std::size_t repeated_timestamps_dropped = 0;
  bool was_sorted = false;  // true when the lines were out of time order and got sorted
};

TrajectoryFile readTrajectoryFile(const std::string& path, TrajectoryFormat format,
                                  TimestampPolicy policy = TimestampPolicy::kTolerant);

// The poses of readTrajectoryFile(path, format, kTolerant); its warnings are discarded.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format);
inline Trajectory readTrajectoryTum(const std::string& path) {
  return readTrajectory(path, TrajectoryFormat::kTum);
}

// TUM format with a header comment. Timestamps print with 9 decimals (nanoseconds) when
// that reproduces the double exactly, else with 17 significant digits; pose numbers print
// with 17 significant digits, so that reading the file back gives bit-identical values.
void writeTrajectoryTum(const std::string& path, const Trajectory& trajectory);

}  // namespace omnidso
