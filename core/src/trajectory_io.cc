// Trajectory file readers and the TUM writer (formats in trajectory_io.hpp).
#include <Eigen/SVD>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <omnidso/core/error.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <string>
#include <vector>

namespace omnidso {
namespace {

// Printed files lose digits: |q| within this of 1 is a unit quaternion printed with about
// six decimals; anything further off is not a rotation.
constexpr double kQuaternionNormTolerance = 1e-3;

struct LineReader {
  const std::string& path;
  int line_number;

  [[noreturn]] void fail(const std::string& message) const {
    throw fileError(path, line_number, message);
  }

  double number(const std::string& field, std::size_t column) const {
    double value = 0.0;
    const char* begin = field.data();
    const char* end = begin + field.size();
    // Leading '+' is not accepted by from_chars but is valid in numeric text.
    if (begin != end && *begin == '+') ++begin;
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec != std::errc() || ptr != end) {
      fail("field " + std::to_string(column + 1) + " '" + field + "' is not a number");
    }
    if (!std::isfinite(value)) {
      fail("field " + std::to_string(column + 1) + " '" + field + "' is not finite");
    }
    return value;
  }
};

// Splits on runs of white space and commas.
std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string current;
  for (const char c : line) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      if (!current.empty()) fields.push_back(std::move(current));
      current.clear();
    } else {
      current.push_back(c);
    }
  }
  if (!current.empty()) fields.push_back(std::move(current));
  return fields;
}

bool isSkippable(const std::string& line) {
  const std::size_t first = line.find_first_not_of(" \t\r\n");
  return first == std::string::npos || line[first] == '#';
}

// Unit quaternion from file values (x, y, z, w): normalised if slightly off; kept bit for
// bit when already unit to double precision, so that written files round-trip exactly.
Eigen::Quaterniond unitQuaternion(const LineReader& reader, double x, double y, double z,
                                  double w) {
  const Eigen::Quaterniond q(w, x, y, z);
  const double norm = q.norm();
  if (std::abs(norm - 1.0) > kQuaternionNormTolerance) {
    reader.fail("quaternion norm " + std::to_string(norm) + " is not 1");
  }
  if (std::abs(q.squaredNorm() - 1.0) <= 4 * std::numeric_limits<double>::epsilon()) return q;
  return q.normalized();
}

SE3d poseFromQuaternion(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  const double params[7] = {q.x(), q.y(), q.z(), q.w(), t.x(), t.y(), t.z()};
  return SE3d::fromParameters(params);
}

// A printed 3×4 rotation is orthonormal only to its printed digits; the nearest rotation
// (polar decomposition R = U Vᵀ) is used. Matrices far from a rotation are rejected.
SE3d poseFromMatrix(const LineReader& reader, const Eigen::Matrix3d& m, const Eigen::Vector3d& t) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  if (std::abs(sv(0) - 1.0) > kQuaternionNormTolerance ||
      std::abs(sv(2) - 1.0) > kQuaternionNormTolerance || m.determinant() < 0.0) {
    reader.fail("3x3 block is not a rotation matrix");
  }
  const Eigen::Matrix3d r = svd.matrixU() * svd.matrixV().transpose();
  return SE3d(Eigen::Quaterniond(r).normalized(), t);
}

// EuRoC timestamps are integer nanoseconds (19 digits, beyond a double's 16): split into
// seconds and remainder before converting so that no precision is lost needlessly.
double nanosecondsToSeconds(const LineReader& reader, const std::string& field) {
  std::int64_t ns = 0;
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, ns);
  if (ec == std::errc() && ptr == end) {
    return static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) * 1e-9;
  }
  return reader.number(field, 0) * 1e-9;
}

StampedPose parseLine(const LineReader& reader, const std::vector<std::string>& fields,
                      TrajectoryFormat format, std::size_t pose_index) {
  auto num = [&](std::size_t column) { return reader.number(fields[column], column); };
  switch (format) {
    case TrajectoryFormat::kTum: {
      if (fields.size() != 8) {
        reader.fail("expected 8 fields 't tx ty tz qx qy qz qw', found " +
                    std::to_string(fields.size()));
      }
      const double t = num(0);
      const Eigen::Vector3d p(num(1), num(2), num(3));
      const Eigen::Quaterniond q = unitQuaternion(reader, num(4), num(5), num(6), num(7));
      return {t, poseFromQuaternion(q, p)};
    }
    case TrajectoryFormat::kKitti: {
      if (fields.size() != 12) {
        reader.fail("expected 12 fields (3x4 pose matrix, row-major), found " +
                    std::to_string(fields.size()));
      }
      Eigen::Matrix3d r;
      Eigen::Vector3d p;
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) r(row, col) = num(static_cast<std::size_t>(4 * row + col));
        p(row) = num(static_cast<std::size_t>(4 * row + 3));
      }
      return {static_cast<double>(pose_index), poseFromMatrix(reader, r, p)};
    }
    case TrajectoryFormat::kEuroc: {
      if (fields.size() < 8) {
        reader.fail("expected at least 8 fields 't_ns, px, py, pz, qw, qx, qy, qz', found " +
                    std::to_string(fields.size()));
      }
      for (std::size_t c = 1; c < fields.size(); ++c) num(c);  // extra columns must be numbers too
      const double t = nanosecondsToSeconds(reader, fields[0]);
      const Eigen::Vector3d p(num(1), num(2), num(3));
      const Eigen::Quaterniond q = unitQuaternion(reader, num(5), num(6), num(7), num(4));
      return {t, poseFromQuaternion(q, p)};
    }
  }
  reader.fail("unknown trajectory format");
}

// Shortest of "%.9f" and "%.17g" that reads back as the same double.
std::string formatTimestamp(double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.9f", t);
  if (std::strtod(buffer, nullptr) == t) return buffer;
  std::snprintf(buffer, sizeof(buffer), "%.17g", t);
  return buffer;
}

// Editors on Windows start UTF-8 files with it; it is not part of the first field.
constexpr const char* kUtf8ByteOrderMark = "\xEF\xBB\xBF";

struct NumberedPose {
  StampedPose pose;
  int line;  // in the file, for messages
};

// Lines out of time order: refused (strict) or stably sorted, so that of equal timestamps
// the one earlier in the file stays first.
void putInTimeOrder(const std::string& path, TimestampPolicy policy,
                    std::vector<NumberedPose>& poses, TrajectoryFile& file) {
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const double previous = poses[i - 1].pose.timestamp;
    const double current = poses[i].pose.timestamp;
    if (current >= previous) continue;
    if (policy == TimestampPolicy::kStrict) {
      throw fileError(path, poses[i].line,
                      "timestamp " + formatTimestamp(current) + " is before the previous one " +
                          formatTimestamp(previous) + " (line " +
                          std::to_string(poses[i - 1].line) + ")");
    }
    file.was_sorted = true;
    file.warnings.push_back(path + ": lines are not in time order (first at line " +
                            std::to_string(poses[i].line) + "); sorted by timestamp");
    std::stable_sort(poses.begin(), poses.end(), [](const NumberedPose& a, const NumberedPose& b) {
      return a.pose.timestamp < b.pose.timestamp;
    });
    return;
  }
}

// Equal timestamps after sorting: the first pose is kept, the others are dropped (evo's
// association also matches the first of equal stamps); refused when strict.
void dropRepeatedTimestamps(const std::string& path, TimestampPolicy policy,
                            std::vector<NumberedPose>& poses, TrajectoryFile& file) {
  std::vector<NumberedPose> kept;
  kept.reserve(poses.size());
  int first_dropped_line = 0;
  for (NumberedPose& numbered : poses) {
    if (!kept.empty() && numbered.pose.timestamp == kept.back().pose.timestamp) {
      if (policy == TimestampPolicy::kStrict) {
        throw fileError(path, numbered.line,
                        "timestamp " + formatTimestamp(numbered.pose.timestamp) +
                            " repeats the one of line " + std::to_string(kept.back().line));
      }
      if (file.repeated_timestamps_dropped++ == 0) first_dropped_line = numbered.line;
      continue;
    }
    kept.push_back(std::move(numbered));
  }
  if (file.repeated_timestamps_dropped > 0) {
    file.warnings.push_back(path + ": " + std::to_string(file.repeated_timestamps_dropped) +
                            " pose(s) with a repeated timestamp dropped, the first of each kept "
                            "(first at line " + std::to_string(first_dropped_line) + ")");
  }
  poses = std::move(kept);
}

}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  throw Error("unknown trajectory format '" + name + "' (expected tum, kitti or euroc)");
}

TrajectoryFile readTrajectoryFile(const std::string& path, TrajectoryFormat format,
                                  TimestampPolicy policy) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open trajectory file");
  std::vector<NumberedPose> read;
  std::string line;
  LineReader reader{path, 0};
  while (std::getline(in, line)) {
    ++reader.line_number;
    if (reader.line_number == 1 && line.rfind(kUtf8ByteOrderMark, 0) == 0) {
      line.erase(0, std::string(kUtf8ByteOrderMark).size());
    }
    if (isSkippable(line)) continue;
    read.push_back({parseLine(reader, splitFields(line), format, read.size()), reader.line_number});
  }
  if (in.bad()) throw fileError(path, "read error");
  if (read.empty()) throw fileError(path, "no poses in trajectory file");
  TrajectoryFile file;
  putInTimeOrder(path, policy, read, file);
  dropRepeatedTimestamps(path, policy, read, file);
  file.poses.reserve(read.size());
  for (NumberedPose& numbered : read) file.poses.push_back(std::move(numbered.pose));
  return file;
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  return readTrajectoryFile(path, format, TimestampPolicy::kTolerant).poses;
}

void writeTrajectoryTum(const std::string& path, const Trajectory& trajectory) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) throw fileError(path, "cannot open for writing");
  std::fprintf(file, "# timestamp tx ty tz qx qy qz qw\n");
  for (const StampedPose& stamped : trajectory) {
    double p[7];
    stamped.pose.toParameters(p);  // [qx qy qz qw tx ty tz]
    std::fprintf(file, "%s %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                 formatTimestamp(stamped.timestamp).c_str(), p[4], p[5], p[6], p[0], p[1], p[2],
                 p[3]);
  }
  const bool write_failed = std::ferror(file) != 0;
  if (std::fclose(file) != 0 || write_failed) throw fileError(path, "write failed");
}

}  // namespace omnidso
