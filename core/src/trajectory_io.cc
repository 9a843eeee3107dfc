// Trajectory file readers and the TUM writer (formats in trajectory_io.hpp).
#include <Eigen/SVD>
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

}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  throw Error("unknown trajectory format '" + name + "' (expected tum, kitti or euroc)");
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open trajectory file");
  Trajectory trajectory;
  std::string line;
  LineReader reader{path, 0};
  while (std::getline(in, line)) {
    ++reader.line_number;
    if (isSkippable(line)) continue;
    StampedPose pose = parseLine(reader, splitFields(line), format, trajectory.size());
    if (!trajectory.empty() && !(pose.timestamp > trajectory.back().timestamp)) {
      reader.fail("timestamp " + formatTimestamp(pose.timestamp) +
                  " is not after the previous one " +
                  formatTimestamp(trajectory.back().timestamp));
    }
    trajectory.push_back(std::move(pose));
  }
  if (trajectory.empty()) throw fileError(path, "no poses in trajectory file");
  return trajectory;
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
