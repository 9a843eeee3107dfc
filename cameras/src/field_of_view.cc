#include "omnidso/cameras/field_of_view.hpp"

#include <algorithm>
#include <cmath>

namespace omnidso {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// Valid on the closed image rectangle [−0.5, w−0.5] × [−0.5, h−0.5]: the field of view
// reaches the outer edge of the border pixels, so the far edge counts too.
bool validOnClosedImage(const Camera& camera, const Eigen::Vector2d& uv) {
  const bool inside = uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() <= camera.width() - 0.5 &&
                      uv.y() <= camera.height() - 0.5;
  return inside && roundTripsThroughModel(camera, uv);
}

Eigen::Vector2d principalPoint(const Camera& camera) {
  const Eigen::VectorXd p = camera.params();
  return {std::clamp(p[2], -0.5, camera.width() - 0.5),
          std::clamp(p[3], -0.5, camera.height() - 0.5)};
}

// Angle between the optical axis and the bearing of the valid pixel nearest `target` on
// the segment from the principal point (radians); 0 if the principal point is invalid.
double angleFromAxisTowards(const Camera& camera, const Eigen::Vector2d& target) {
  const Eigen::Vector2d centre = principalPoint(camera);
  if (!validOnClosedImage(camera, centre)) return 0.0;
  Eigen::Vector3d bearing;
  if (!camera.unproject(lastValidPixelTowards(camera, centre, target), bearing)) return 0.0;
  return std::acos(std::clamp(bearing.z(), -1.0, 1.0));
}

double acrossDeg(const Camera& camera, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (angleFromAxisTowards(camera, a) + angleFromAxisTowards(camera, b)) * kRadToDeg;
}

}  // namespace

Eigen::Vector2d lastValidPixelTowards(const Camera& camera, const Eigen::Vector2d& inside,
                                      const Eigen::Vector2d& target) {
  if (validOnClosedImage(camera, target)) return target;
  // Invariant: `good` is valid, `bad` is not; halve until 1e-6 px apart.
  Eigen::Vector2d good = inside;
  Eigen::Vector2d bad = target;
  while ((bad - good).norm() > 1e-6) {
    const Eigen::Vector2d mid = 0.5 * (good + bad);
    (validOnClosedImage(camera, mid) ? good : bad) = mid;
  }
  return good;
}

double horizontalFovDeg(const Camera& camera) {
  const double row = principalPoint(camera).y();
  return acrossDeg(camera, {-0.5, row}, {camera.width() - 0.5, row});
}

double verticalFovDeg(const Camera& camera) {
  const double column = principalPoint(camera).x();
  return acrossDeg(camera, {column, -0.5}, {column, camera.height() - 0.5});
}

double diagonalFovDeg(const Camera& camera) {
  const double right = camera.width() - 0.5;
  const double bottom = camera.height() - 0.5;
  return std::max(acrossDeg(camera, {-0.5, -0.5}, {right, bottom}),
                  acrossDeg(camera, {right, -0.5}, {-0.5, bottom}));
}

double maximumFovDeg(const Camera& camera) {
  // Every model's angle from the axis grows with the distance from the principal point, so
  // the maximum lies on the boundary of the valid region; rays to each border position at
  // 1 px spacing reach all of it (the image circle where the border is invalid).
  const double right = camera.width() - 0.5;
  const double bottom = camera.height() - 0.5;
  double max_angle = 0.0;
  const auto visit = [&](double u, double v) {
    max_angle = std::max(max_angle, angleFromAxisTowards(camera, {u, v}));
  };
  for (int i = 0; i <= camera.width(); ++i) {
    visit(i - 0.5, -0.5);
    visit(i - 0.5, bottom);
  }
  for (int j = 0; j <= camera.height(); ++j) {
    visit(-0.5, j - 0.5);
    visit(right, j - 0.5);
  }
  return 2.0 * max_angle * kRadToDeg;
}

double validPixelFraction(const Camera& camera) {
  const Mask mask = validityMask(camera);
  const auto valid =
      std::count_if(mask.data(), mask.data() + mask.size(), [](std::uint8_t m) { return m != 0; });
  return static_cast<double>(valid) / static_cast<double>(mask.size());
}

FieldOfView fieldOfView(const Camera& camera) {
  FieldOfView fov;
  fov.horizontal_deg = horizontalFovDeg(camera);
  fov.vertical_deg = verticalFovDeg(camera);
  fov.diagonal_deg = diagonalFovDeg(camera);
  fov.maximum_deg = maximumFovDeg(camera);
  fov.valid_pixel_fraction = validPixelFraction(camera);
  return fov;
}

}  // namespace omnidso
