// KITTI odometry's calib.txt (format in calibration_io.hpp): image_0's pinhole from the P0
// line. The file holds no image size, so the caller passes the images' (datasetCamera).
#include <algorithm>
#include <array>
#include <fstream>
#include <vector>

#include <fmt/format.h>

#include "calibration_kitti.hpp"
#include "calibration_text.hpp"
#include "omnidso/cameras/calibration_io.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

constexpr int kProjectionValues = 12;  // a 3×4 matrix, row-major

// The numbers after "P0:" on line `line_no`; every one finite, twelve of them.
std::array<double, kProjectionValues> projectionMatrix(const std::string& path, int line_no,
                                                       const std::string& numbers) {
  const std::vector<double> values =
      detail::finiteNumbers(path, line_no, detail::textTokens(numbers), 0, "P0: ");
  if (values.size() != kProjectionValues) {
    throw fileError(path, line_no,
                    fmt::format("P0 takes {} numbers (a 3x4 projection matrix, row-major), got {}",
                                kProjectionValues, values.size()));
  }
  std::array<double, kProjectionValues> matrix{};
  std::copy(values.begin(), values.end(), matrix.begin());
  return matrix;
}

}  // namespace

bool detail::isKittiP0Line(const std::string& line) {
  const std::size_t start = line.find_first_not_of(" \t");
  return start != std::string::npos && line.compare(start, 3, "P0:") == 0;
}

Camera loadKittiCalib(const std::string& path, int width, int height) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open calibration file");
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!detail::isKittiP0Line(line)) continue;
    const std::array<double, kProjectionValues> p =
        projectionMatrix(path, line_no, line.substr(line.find("P0:") + 3));
    // P0 = K·[I | t] of the rectified image_0: K = [fx 0 cx; 0 fy cy; 0 0 1]. Anything else
    // (a skew, a rotation) is not a pinhole on these pixels and would be read wrong.
    if (p[1] != 0.0 || p[4] != 0.0 || p[8] != 0.0 || p[9] != 0.0 || p[10] != 1.0) {
      throw fileError(path, line_no,
                      "P0 is not a rectified pinhole K·[I|t] (expected entries 2 and 5 to be 0 "
                      "and the third row to start with 0 0 1)");
    }
    const double fx = p[0], cx = p[2], fy = p[5], cy = p[6];
    if (!(fx > 0.0) || !(fy > 0.0)) {
      throw fileError(path, line_no,
                      fmt::format("P0: focal lengths must be positive, got fx {} and fy {}", fx,
                                  fy));
    }
    // KITTI's principal point is in OpenCV's convention, the top-left pixel's centre at
    // (0, 0), as this project's: no half-pixel shift.
    Eigen::VectorXd params(4);
    params << fx, fy, cx, cy;
    try {
      return Camera::create("pinhole", params, width, height);
    } catch (const Error& e) {
      throw fileError(path, line_no, e.what());
    }
  }
  throw fileError(path, "no 'P0:' line (KITTI's calib.txt holds image_0's projection there)");
}

}  // namespace omnidso
