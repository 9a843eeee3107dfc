#pragma once
// A small analytic renderer for residual tests: the camera sits inside a textured sphere
// (off-centre, so distances vary over the image); the texture is a smooth function of the
// 3D point. An image is rendered through any camera model by unprojecting each pixel
// centre and intersecting its ray with the sphere, with the image formation of eq. 5:
//   I = t · e^{a} · texture(X) + b,
// so that the photometric residual of a pixel at its true inverse distance is zero up to
// the bilinear interpolation error of the rendered target image.

#include <Eigen/Core>
#include <cmath>

#include "omnidso/core/image.hpp"
#include "omnidso/core/se3.hpp"

namespace omnidso::test {

struct Photometry {
  double exposure = 1.0;  // t
  double a = 0.0;
  double b = 0.0;
};

struct SphereScene {
  Eigen::Vector3d centre{0.3, -0.2, 0.5};
  double radius = 4.0;

  // Wavelengths ≥ 1.6 m: ≥ ~30 px at the test focal lengths and distances, so that bilinear
  // interpolation of the rendered images errs by well under one intensity unit.
  double texture(const Eigen::Vector3d& X) const {
    return 128.0 + 50.0 * std::sin(1.5 * X.x()) * std::cos(1.2 * X.y()) +
           35.0 * std::sin(2.5 * X.z() + 1.7 * X.x()) + 20.0 * std::cos(3.1 * X.y() - 2.3 * X.z());
  }

  // Distance along the unit ray origin + s·direction to the sphere (the origin is inside,
  // so exactly one root is positive).
  double distance(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
    const Eigen::Vector3d oc = origin - centre;
    const double half_b = direction.dot(oc);
    const double c = oc.squaredNorm() - radius * radius;
    return -half_b + std::sqrt(half_b * half_b - c);
  }

  // Distance from the camera centre to the scene along a unit bearing in the camera frame.
  double distanceAlong(const SE3d& T_world_cam, const Eigen::Vector3d& bearing) const {
    return distance(T_world_cam.translation(), T_world_cam.rotation() * bearing);
  }

  // Pixels that do not unproject are left at 0 (no test samples them).
  template <typename Camera>
  ImageF render(const Camera& camera, const SE3d& T_world_cam, int width, int height,
                const Photometry& photometry) const {
    ImageF image(width, height, 0.0f);
    const double gain = photometry.exposure * std::exp(photometry.a);
    for (int v = 0; v < height; ++v) {
      for (int u = 0; u < width; ++u) {
        Eigen::Vector3d bearing;
        if (!camera.unproject(Eigen::Vector2d(u, v), bearing)) continue;
        const Eigen::Vector3d X = T_world_cam * (distanceAlong(T_world_cam, bearing) * bearing);
        image(u, v) = static_cast<float>(gain * texture(X) + photometry.b);
      }
    }
    return image;
  }
};

}  // namespace omnidso::test
