// Rectification maps and resampling (rectification.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cameras/rectification.hpp>
#include <omnidso/core/error.hpp>

#include "vector_literal.hpp"

namespace omnidso {
namespace {

using test::vec;

// A smooth scene painted on the sphere of directions, so that the same ray has the same
// intensity in every camera.
float sceneIntensity(const Eigen::Vector3d& bearing) {
  return static_cast<float>(100.0 +
                            50.0 * std::sin(4.0 * bearing.x()) * std::cos(3.0 * bearing.y()));
}

ImageF render(const Camera& camera) {
  ImageF image(camera.width(), camera.height(), 0.0f);
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) {
      Eigen::Vector3d b;
      if (camera.unproject(Eigen::Vector2d(u, v), b)) image(u, v) = sceneIntensity(b);
    }
  }
  return image;
}

TEST(RectificationTest, PinholeForFovHasThatFieldOfView) {
  const Camera camera = pinholeForFov(90.0, 640, 480);
  EXPECT_EQ(camera.modelName(), "pinhole");
  EXPECT_EQ(camera.width(), 640);
  EXPECT_EQ(camera.height(), 480);
  EXPECT_NEAR(camera.params()[0], 320.0, 1e-12);  // (w/2)/tan 45°
  EXPECT_NEAR(camera.params()[2], 319.5, 0.0);
  EXPECT_NEAR(horizontalFovDeg(camera), 90.0, 1e-9);
  EXPECT_THROW(pinholeForFov(180.0, 640, 480), Error);
}

// At the principal point a unified camera spans f / (1 + ξ) pixels per radian and a pinhole f:
// the crop magnifies by f_pinhole (1 + ξ) / f_ucm, to the second order of the half-pixel
// steps (1e-4 relative). A camera magnifies itself by 1.
TEST(RectificationTest, MagnificationAtPrincipalPointIsTheRatioOfAngularResolutions) {
  const Camera fisheye = Camera::create("ucm", vec({190.0, 190.0, 239.5, 239.5, 1.05}), 480, 480);
  const Camera crop = pinholeForFov(90.0, 480, 480);
  EXPECT_NEAR(magnificationAtPrincipalPoint(fisheye, crop), 240.0 * 2.05 / 190.0, 1e-4 * 2.59);
  EXPECT_NEAR(magnificationAtPrincipalPoint(crop, fisheye), 190.0 / (240.0 * 2.05), 1e-4 * 0.39);
  EXPECT_NEAR(magnificationAtPrincipalPoint(fisheye, fisheye), 1.0, 1e-9);
}

TEST(RectificationTest, IdentityMapPointsToTheSamePixel) {
  const Camera camera = Camera::create("pinhole", vec({400, 400, 319.5, 239.5}), 64, 48);
  const RectificationMap map = makeRectificationMap(camera, camera);
  for (int v = 0; v < 48; ++v) {
    for (int u = 0; u < 64; ++u) {
      ASSERT_TRUE(map.valid(u, v));
      // float storage: ~1e-5 relative at coordinates below 64.
      EXPECT_NEAR(map.source_u[map.index(u, v)], u, 1e-3);
      EXPECT_NEAR(map.source_v[map.index(u, v)], v, 1e-3);
    }
  }
}

// Raw (radial–tangential) image → the undistorted pinhole image: the rectified image shows
// the scene as the distortion-free camera would. Bilinear interpolation errs by at most
// h²/8·(|I_uu| + |I_vv|) with h = 1 px; the scene's second derivatives in pixels are below
// 50·(4² + 3²)/f² ≈ 6e-3 grey levels/px² at f ≈ 458, so 0.01 is a safe bound (plus float
// rounding of the coordinates).
TEST(RectificationTest, UndistortsARawImage) {
  const Camera raw = Camera::create(
      "pinhole-radtan", vec({458.654, 457.296, 367.215, 248.375, -0.2834, 0.0740, 1.9e-4, 1.8e-5}),
      752, 480);
  const Camera undistorted = raw.undistortedModel();
  const RectificationMap map = makeRectificationMap(raw, undistorted);
  const ImageF rectified = remap(render(raw), map);
  const ImageF expected = render(undistorted);
  int checked = 0;
  double max_error = 0.0;
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 752; ++u) {
      if (!map.valid(u, v)) continue;
      ++checked;
      max_error =
          std::max(max_error, std::abs(static_cast<double>(rectified(u, v) - expected(u, v))));
    }
  }
  EXPECT_LT(max_error, 0.01);
  // Barrel distortion (k1 < 0) squeezes the periphery into the raw image, so the raw image
  // sees more than the undistorted view with the same K: every output pixel has a source
  // (the output corner (0, 0) comes from raw pixel ≈ (74, 51)).
  EXPECT_EQ(checked, 752 * 480);
  // The reverse direction does not cover: raw corners lie outside the undistorted image.
  const Mask reverse = validMask(makeRectificationMap(undistorted, raw));
  EXPECT_EQ(reverse(0, 0), 0);
  EXPECT_NE(reverse(376, 240), 0);
}

TEST(RectificationTest, FisheyeToRotatedPinholeCrop) {
  const Camera fisheye = Camera::create("ucm", vec({300.0, 301.0, 239.2, 240.6, 0.95}), 480, 480);
  const Camera crop = pinholeForFov(90.0, 320, 240);
  // The crop looks 20° to the right of the fisheye's axis: R_src_dst rotates about y.
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(20.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const RectificationMap map =
      makeRectificationMap(fisheye, crop, SE3d(R, Eigen::Vector3d::Zero()));
  // The crop's principal ray is R·e_z in the fisheye; float storage → 1e-3 px.
  Eigen::Vector2d centre;
  ASSERT_TRUE(fisheye.project(R * Eigen::Vector3d::UnitZ(), centre));
  // The crop's pixel (159.5, 119.5) is its principal point: average the four around it.
  double u_sum = 0.0;
  double v_sum = 0.0;
  for (const auto& [u, v] : {std::pair{159, 119}, {160, 119}, {159, 120}, {160, 120}}) {
    u_sum += map.source_u[map.index(u, v)];
    v_sum += map.source_v[map.index(u, v)];
  }
  // Averaging is exact for an affine map; the curvature of the fisheye over ±0.5 px adds
  // well under 0.01 px.
  EXPECT_NEAR(u_sum / 4.0, centre.x(), 0.01);
  EXPECT_NEAR(v_sum / 4.0, centre.y(), 0.01);
  // 90° × 74° around a ray 20° off axis lies inside this fisheye (±75° at the border
  // midpoints, ≈90° in the corners): the far corner of the crop lands near u = 421 < 479.5.
  const Mask mask = validMask(map);
  EXPECT_EQ(std::count(mask.data(), mask.data() + mask.size(), 0), 0);
}

TEST(RectificationTest, RemapU8RoundsAndFillsInvalid) {
  const Camera small = Camera::create("pinhole", vec({10, 10, 1.5, 1.5}), 4, 4);
  RectificationMap map = makeRectificationMap(small, small);
  map.source_u[map.index(3, 3)] = RectificationMap::kInvalid;
  map.source_v[map.index(3, 3)] = RectificationMap::kInvalid;
  map.source_u[map.index(0, 0)] = 0.5f;  // between columns 0 and 1
  ImageU8 src(4, 4, 0);
  src(0, 0) = 10;
  src(1, 0) = 21;
  const ImageU8 out = remap(src, map, 7);
  EXPECT_EQ(out(0, 0), 16);  // (10 + 21)/2 = 15.5 rounds to 16
  EXPECT_EQ(out(3, 3), 7);
  EXPECT_EQ(out(1, 0), 21);
}

}  // namespace
}  // namespace omnidso
