#include "omnidso/cameras/rectification.hpp"

#include <algorithm>
#include <cmath>

#include "omnidso/core/error.hpp"
#include "omnidso/core/interpolation.hpp"

namespace omnidso {
namespace {

template <typename Pixel>
Image<Pixel> remapImpl(const Image<Pixel>& src, const RectificationMap& map, Pixel fill,
                       bool round) {
  Image<Pixel> out(map.width, map.height, fill);
  ImageF src_f(src.width(), src.height());
  std::transform(src.data(), src.data() + src.size(), src_f.data(),
                 [](Pixel p) { return static_cast<float>(p); });
  const double max_u = src.width() - 1.0;
  const double max_v = src.height() - 1.0;
  for (int v = 0; v < map.height; ++v) {
    for (int u = 0; u < map.width; ++u) {
      if (!map.valid(u, v)) continue;
      const size_t i = map.index(u, v);
      // The map holds pixels of [−0.5, w−0.5): clamp the half-pixel rims to the centres.
      const double su = std::clamp(static_cast<double>(map.source_u[i]), 0.0, max_u);
      const double sv = std::clamp(static_cast<double>(map.source_v[i]), 0.0, max_v);
      double value = 0.0;
      if (!sampleBilinear(src_f, su, sv, &value)) continue;
      out(u, v) = static_cast<Pixel>(round ? std::lround(value) : value);
    }
  }
  return out;
}

}  // namespace

RectificationMap makeRectificationMap(const Camera& src, const Camera& dst,
                                      const Eigen::Matrix3d& R_src_dst) {
  RectificationMap map;
  map.width = dst.width();
  map.height = dst.height();
  const size_t n = static_cast<size_t>(map.width) * map.height;
  map.source_u.assign(n, RectificationMap::kInvalid);
  map.source_v.assign(n, RectificationMap::kInvalid);
  for (int v = 0; v < map.height; ++v) {
    for (int u = 0; u < map.width; ++u) {
      Eigen::Vector3d bearing;
      Eigen::Vector2d uv_src;
      if (!isValidPixel(dst, Eigen::Vector2d(u, v)) ||
          !dst.unproject(Eigen::Vector2d(u, v), bearing) ||
          !src.project(R_src_dst * bearing, uv_src)) {
        continue;
      }
      map.source_u[map.index(u, v)] = static_cast<float>(uv_src.x());
      map.source_v[map.index(u, v)] = static_cast<float>(uv_src.y());
    }
  }
  return map;
}

RectificationMap makeRectificationMap(const Camera& src, const Camera& dst, const SE3d& T_src_dst) {
  return makeRectificationMap(src, dst, T_src_dst.rotationMatrix());
}

ImageF remap(const ImageF& src, const RectificationMap& map, float fill) {
  return remapImpl(src, map, fill, false);
}

ImageU8 remap(const ImageU8& src, const RectificationMap& map, std::uint8_t fill) {
  return remapImpl(src, map, fill, true);
}

Mask validMask(const RectificationMap& map) {
  Mask mask(map.width, map.height, 0);
  for (int v = 0; v < map.height; ++v) {
    for (int u = 0; u < map.width; ++u) mask(u, v) = map.valid(u, v) ? 255 : 0;
  }
  return mask;
}

Camera pinholeForFov(double fov_deg, int width, int height) {
  if (!(fov_deg > 0.0 && fov_deg < 180.0)) {
    throw Error("pinhole field of view must be in (0, 180) degrees, got " +
                std::to_string(fov_deg));
  }
  const double f = 0.5 * width / std::tan(0.5 * fov_deg * M_PI / 180.0);
  Eigen::VectorXd p(4);
  p << f, f, 0.5 * (width - 1), 0.5 * (height - 1);
  return Camera::create("pinhole", p, width, height);
}

namespace {

// The angle between the rays of two pixels of a camera.
double angleBetween(const Camera& camera, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  Eigen::Vector3d ra, rb;
  if (!camera.unproject(a, ra) || !camera.unproject(b, rb))
    throw Error("magnificationAtPrincipalPoint: a pixel near the principal point of the " +
                camera.modelName() + " camera does not unproject");
  ra.normalize();
  rb.normalize();
  return std::atan2(ra.cross(rb).norm(), ra.dot(rb));
}

}  // namespace

double magnificationAtPrincipalPoint(const Camera& source, const Camera& target) {
  const Eigen::VectorXd p = target.params();
  const Eigen::Vector2d centre(p[2], p[3]);
  Eigen::Vector3d ray;
  Eigen::Vector2d in_source;
  if (!target.unproject(centre, ray) || !source.project(ray, in_source))
    throw Error("magnificationAtPrincipalPoint: the " + target.modelName() +
                " camera's principal ray does not reach the " + source.modelName() + " camera");
  const Eigen::Vector2d step(0.5, 0.0);  // ± half a pixel: one pixel, centred on the ray
  return angleBetween(source, in_source - step, in_source + step) /
         angleBetween(target, centre - step, centre + step);
}

}  // namespace omnidso
