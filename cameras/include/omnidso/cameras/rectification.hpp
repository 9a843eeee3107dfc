#pragma once
// Resampling an image from one camera to another with a common optical centre: the raw
// (radial–tangential) image to its undistorted model image, or a fisheye image to the
// cropped pinhole view the paper compares against ("DSO with pinhole model").
//
// For each output pixel p: bearing b = π_dst⁻¹(p) in the destination frame, rotated into the
// source frame, b' = R_src_dst·b, and its source pixel π_src(b'). The map stores that source
// pixel; remap() samples it bilinearly.

#include <Eigen/Core>
#include <vector>

#include "omnidso/cameras/camera.hpp"
#include "omnidso/core/image.hpp"
#include "omnidso/core/se3.hpp"

namespace omnidso {

struct RectificationMap {
  // Marks an output pixel with no source pixel (outside the source image or either model's
  // domain). Any coordinate this negative lies far outside every image.
  static constexpr float kInvalid = -1e6f;

  int width = 0;
  int height = 0;
  std::vector<float> source_u;  // row-major, width × height
  std::vector<float> source_v;

  bool valid(int u, int v) const { return source_u[index(u, v)] != kInvalid; }
  size_t index(int u, int v) const { return static_cast<size_t>(v) * width + u; }
};

RectificationMap makeRectificationMap(
    const Camera& src, const Camera& dst,
    const Eigen::Matrix3d& R_src_dst = Eigen::Matrix3d::Identity());
// Only the rotation of T_src_dst is used: rectification cannot undo a translation.
RectificationMap makeRectificationMap(const Camera& src, const Camera& dst, const SE3d& T_src_dst);

// Bilinear resampling; invalid output pixels get `fill`. Source coordinates between the
// outermost pixel centre and the image edge (e.g. u ∈ [−0.5, 0)) take the border pixel.
ImageF remap(const ImageF& src, const RectificationMap& map, float fill = 0.0f);
ImageU8 remap(const ImageU8& src, const RectificationMap& map, std::uint8_t fill = 0);
// Non-zero where the map has a source pixel.
Mask validMask(const RectificationMap& map);

// A centred pinhole camera with horizontal field of view fov_deg (0 < fov_deg < 180):
// fx = fy = (w/2) / tan(fov/2), principal point at the image centre ((w−1)/2, (h−1)/2), so
// that horizontalFovDeg() of the result is fov_deg.
Camera pinholeForFov(double fov_deg, int width, int height);

// How much `target` magnifies `source` at target's principal point: the angle one source pixel
// spans there over the angle one target pixel spans, both measured horizontally around the
// ray through the target's principal point (for a 90° 480-pixel pinhole crop of a unified
// fisheye with f = 190, ξ = 1.05: (f/(1+ξ))⁻¹ / 240⁻¹ ≈ 2.59). Throws omnidso::Error when the
// ray or its neighbours do not (un)project in either camera.
double magnificationAtPrincipalPoint(const Camera& source, const Camera& target);

}  // namespace omnidso
