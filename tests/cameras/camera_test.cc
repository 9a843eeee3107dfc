// The runtime Camera (camera.hpp) and its field-of-view figures (field_of_view.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/error.hpp>

#include "vector_literal.hpp"

namespace omnidso {
namespace {

using test::vec;

struct NamedParams {
  std::string name;
  Eigen::VectorXd params;
};

// One realistic calibration per model on a 640×480 image.
std::vector<NamedParams> everyModel() {
  return {{"pinhole", vec({460, 458, 319.5, 239.5})},
          {"ucm", vec({380, 379, 320.2, 239.1, 0.9})},
          {"eucm", vec({250, 251, 320.3, 240.2, 0.6, 1.1})},
          {"ds", vec({180, 181, 319.1, 240.7, 0.2, 0.6})},
          {"kb4", vec({200, 201, 319.4, 239.6, 0.01, -0.005, 0.001, -0.0002})},
          {"pinhole-radtan", vec({458.6, 457.3, 319.2, 240.4, -0.28, 0.07, 2e-4, 1.8e-5})},
          {"ucm-radtan", vec({408.9, 410.5, 320.3, 241.9, 1.05, -0.008, 0.012, 0.002, -0.004})},
          {"fov", vec({223.5, 260.7, 318.4, 238.7, 0.934785})}};
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CameraTest, CreatesEveryModelByNameAndRoundTripsPixels) {
  ASSERT_EQ(everyModel().size(), knownCameraModelNames().size());
  for (const auto& [name, params] : everyModel()) {
    const Camera camera = Camera::create(name, params, 640, 480);
    EXPECT_EQ(camera.modelName(), name);
    EXPECT_EQ(camera.params(), params);
    EXPECT_EQ(camera.paramNames().size(), static_cast<size_t>(params.size()));
    EXPECT_EQ(camera.paramNames()[0], "fx");
    // A pixel near the centre unprojects to a unit bearing that projects back to it; 1e-6 px
    // is far above double rounding and the iterative undistortion's convergence.
    const Eigen::Vector2d uv(250.3, 301.7);
    Eigen::Vector3d bearing;
    Eigen::Vector2d back;
    ASSERT_TRUE(camera.unproject(uv, bearing)) << name;
    EXPECT_NEAR(bearing.norm(), 1.0, 1e-12) << name;
    ASSERT_TRUE(camera.project(bearing * 3.0, back)) << name;
    EXPECT_LT((back - uv).norm(), 1e-6) << name;
    EXPECT_TRUE(isValidPixel(camera, uv)) << name;
  }
}

TEST(CameraTest, AcceptsAliases) {
  EXPECT_EQ(canonicalCameraModelName("kb"), "kb4");
  EXPECT_EQ(canonicalCameraModelName("equidistant"), "kb4");
  EXPECT_EQ(canonicalCameraModelName("omni"), "ucm");
  EXPECT_EQ(canonicalCameraModelName("unified"), "ucm");
  EXPECT_EQ(canonicalCameraModelName("atan"), "fov");
  EXPECT_EQ(Camera::create("omni", vec({300, 300, 320, 240, 1.0}), 640, 480).modelName(), "ucm");
}

TEST(CameraTest, RejectsBadParametersWithReasons) {
  const auto create = [](const std::string& name, const Eigen::VectorXd& p) {
    return errorOf([&] { Camera::create(name, p, 640, 480); });
  };
  const std::string unknown = create("fisheye9000", vec({1, 1, 1, 1}));
  EXPECT_NE(unknown.find("unknown camera model 'fisheye9000'"), std::string::npos) << unknown;
  for (const std::string& known : knownCameraModelNames()) {
    EXPECT_NE(unknown.find(known), std::string::npos) << "lists " << known << ": " << unknown;
  }
  EXPECT_NE(create("ucm", vec({1, 1, 1, 1})).find("takes 5 parameters, got 4"), std::string::npos);
  EXPECT_NE(create("pinhole", vec({NAN, 1, 1, 1})).find("not a finite number"), std::string::npos);
  EXPECT_NE(create("pinhole", vec({0, 1, 1, 1})).find("focal lengths must be positive"),
            std::string::npos);
  EXPECT_NE(create("pinhole", vec({1, -2, 1, 1})).find("focal lengths must be positive"),
            std::string::npos);
  EXPECT_NE(create("ucm", vec({1, 1, 1, 1, -0.1})).find("xi must be >= 0"), std::string::npos);
  EXPECT_NE(create("eucm", vec({1, 1, 1, 1, 1.2, 1})).find("alpha must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(create("eucm", vec({1, 1, 1, 1, 0.5, 0})).find("beta must be > 0"), std::string::npos);
  EXPECT_NE(create("ds", vec({1, 1, 1, 1, -1.0, 0.5})).find("xi must be > -1"), std::string::npos);
  EXPECT_NE(create("ds", vec({1, 1, 1, 1, 0.1, -0.1})).find("alpha must be in [0, 1]"),
            std::string::npos);
  // FOV: ω > 0 (the model divides by it) and ω < π (tan(ω/2) is infinite there).
  for (const double omega : {0.0, -0.5, M_PI, 4.0}) {
    EXPECT_NE(create("fov", vec({1, 1, 1, 1, omega})).find("must be in (0, pi)"),
              std::string::npos)
        << omega;
  }
  EXPECT_EQ(create("fov", vec({1, 1, 1, 1, 1e-6})), "(no error)");
  EXPECT_EQ(create("fov", vec({1, 1, 1, 1, 3.14})), "(no error)");
  EXPECT_NE(errorOf([] {
              Camera::create("pinhole", vec({1, 1, 1, 1}), 0, 480);
            }).find("image size must be in [1, 100000]"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              Camera::create("pinhole", vec({1, 1, 1, 1}), 640, 100001);
            }).find("image size must be in [1, 100000]"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              Camera::create("pinhole", vec({2e6, 1, 1, 1}), 640, 480);
            }).find("focal length"),
            std::string::npos);
  EXPECT_NE(errorOf([] {
              Camera::create("pinhole", vec({1, 1, 1, -3e6}), 640, 480);
            }).find("principal point"),
            std::string::npos);
}

TEST(CameraTest, ProjectRequiresTheImageRectangle) {
  // Pinhole f = 100, c = (319.5, 239.5): x/z = 3.2 lands on u = 639.5, the outer edge.
  const Camera camera = Camera::create("pinhole", vec({100, 100, 319.5, 239.5}), 640, 480);
  Eigen::Vector2d uv;
  EXPECT_TRUE(camera.project({3.19, 0.0, 1.0}, uv));
  EXPECT_FALSE(camera.project({3.2, 0.0, 1.0}, uv));  // u = w − 0.5 is outside [−0.5, w−0.5)
  EXPECT_TRUE(camera.project({-3.195, 0.0, 1.0}, uv));  // u = −0.0 ≥ −0.5
  EXPECT_FALSE(camera.project({0.0, 0.0, -1.0}, uv));   // behind a pinhole
  EXPECT_TRUE(camera.inImage({-0.5, -0.5}));
  EXPECT_FALSE(camera.inImage({639.5, 0.0}));
  EXPECT_FALSE(camera.inImage({1.0, 1.0}, 2.0));
  EXPECT_TRUE(camera.inImage({1.5, 1.5}, 2.0));
}

TEST(CameraTest, PyramidLevelScalesIntrinsicsAndSize) {
  for (const auto& [name, params] : everyModel()) {
    const Camera level0 = Camera::create(name, params, 640, 480);
    const Camera level2 = level0.atPyramidLevel(2);
    EXPECT_EQ(level2.width(), 160);
    EXPECT_EQ(level2.height(), 120);
    EXPECT_EQ(level2.modelName(), name);
    // The same ray lands on the level-2 image of its level-0 pixel (pyramid_scaling.hpp):
    // the map is affine in the pixel, so this holds to rounding.
    const Eigen::Vector3d ray(0.2, -0.1, 1.0);
    Eigen::Vector2d uv0, uv2;
    ASSERT_TRUE(level0.project(ray, uv0));
    ASSERT_TRUE(level2.project(ray, uv2));
    EXPECT_NEAR(uv2.x(), pixelToLevel(uv0.x(), 2), 1e-9) << name;
    EXPECT_NEAR(uv2.y(), pixelToLevel(uv0.y(), 2), 1e-9) << name;
  }
}

TEST(CameraTest, DistortionAndUndistortedModel) {
  const Camera raw = Camera::create("ucm-radtan", everyModel()[6].params, 640, 480);
  EXPECT_TRUE(raw.hasDistortion());
  EXPECT_TRUE(raw.distortsImages());
  const Camera base = raw.undistortedModel();
  EXPECT_FALSE(base.hasDistortion());
  EXPECT_FALSE(base.distortsImages());
  // Zero coefficients (as some calibration files write them): the same images as the base's.
  Eigen::VectorXd zero_params = raw.params();
  zero_params.tail<4>().setZero();
  const Camera zero = Camera::create("ucm-radtan", zero_params, 640, 480);
  EXPECT_TRUE(zero.hasDistortion());
  EXPECT_FALSE(zero.distortsImages());
  zero_params[zero_params.size() - 1] = 1e-4;  // any non-zero coefficient (p2)
  EXPECT_TRUE(Camera::create("ucm-radtan", zero_params, 640, 480).distortsImages());
  EXPECT_EQ(base.modelName(), "ucm");
  EXPECT_EQ(base.params(), raw.params().head(5));
  EXPECT_EQ(base.width(), 640);
  const Camera pinhole_raw = Camera::create("pinhole-radtan", everyModel()[5].params, 752, 480);
  EXPECT_EQ(pinhole_raw.undistortedModel().modelName(), "pinhole");
  const Camera kb = Camera::create("kb4", everyModel()[4].params, 640, 480);
  EXPECT_FALSE(kb.hasDistortion());
  EXPECT_EQ(kb.undistortedModel().params(), kb.params());
  // FOV is a model of its own that the odometry runs on natively, not a distortion of one.
  const Camera fov = Camera::create("fov", everyModel()[7].params, 640, 480);
  EXPECT_FALSE(fov.hasDistortion());
  EXPECT_FALSE(fov.distortsImages());
  EXPECT_EQ(fov.undistortedModel().modelName(), "fov");
  EXPECT_EQ(fov.undistortedModel().params(), fov.params());
}

// UCM with ξ > 1: the image of the sphere is the disc r < 1/√(ξ² − 1) on the normalised
// plane (unified.hpp: the discriminant 1 + (1 − ξ²) r² vanishes there, at the fold).
TEST(CameraTest, ValidityMaskIsTheImageCircle) {
  const double xi = 1.5;
  const double f = 100.0;
  const Camera camera = Camera::create("ucm", vec({f, f, 239.5, 239.5, xi}), 480, 480);
  const double radius_px = f / std::sqrt(xi * xi - 1.0);
  const Mask mask = validityMask(camera);
  int disagreements = 0;
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 480; ++u) {
      const double r = std::hypot(u - 239.5, v - 239.5);
      // 1 px margin: pixel centres within a pixel of the fold are not asserted on.
      if (r < radius_px - 1.0 && mask(u, v) == 0) ++disagreements;
      if (r > radius_px + 1.0 && mask(u, v) != 0) ++disagreements;
    }
  }
  EXPECT_EQ(disagreements, 0);
  // The valid fraction is the disc's area share, up to the 1-px ring around its edge.
  const double expected = M_PI * radius_px * radius_px / (480.0 * 480.0);
  EXPECT_NEAR(validPixelFraction(camera), expected, 2.0 * M_PI * radius_px / (480.0 * 480.0));
  // The disc's edge is the fold at cos θ = −1/ξ: the maximum field of view is 2·acos(−1/ξ).
  // Bisection to 1e-6 px leaves Δθ ≈ √(Δr / r''), well below 0.05°.
  EXPECT_NEAR(maximumFovDeg(camera), 2.0 * std::acos(-1.0 / xi) * 180.0 / M_PI, 0.05);
}

TEST(FieldOfViewTest, PinholeIsTwoArctanOfHalfSizeOverFocal) {
  const double f = 400.0;
  const Camera camera = Camera::create("pinhole", vec({f, f, 319.5, 239.5}), 640, 480);
  const double deg = 180.0 / M_PI;
  // The image spans [−0.5, w − 0.5]: w/2 on either side of c = (w − 1)/2. acos of a bearing
  // component vs atan agree to ~1e-14 rad.
  EXPECT_NEAR(horizontalFovDeg(camera), 2.0 * std::atan(320.0 / f) * deg, 1e-9);
  EXPECT_NEAR(verticalFovDeg(camera), 2.0 * std::atan(240.0 / f) * deg, 1e-9);
  EXPECT_NEAR(diagonalFovDeg(camera), 2.0 * std::atan(400.0 / f) * deg, 1e-9);
  EXPECT_NEAR(maximumFovDeg(camera), 2.0 * std::atan(400.0 / f) * deg, 1e-9);
  EXPECT_DOUBLE_EQ(validPixelFraction(camera), 1.0);
}

// Angle from the axis of a UCM point at normalised radius r: r = sin θ / (cos θ + ξ) (eq. 2),
// increasing in θ up to the fold; solved by bisection independently of unified.hpp.
double ucmAngle(double r, double xi) {
  double lo = 0.0;
  double hi = std::acos(-std::min(xi, 1.0 / xi));
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::sin(mid) / (std::cos(mid) + xi) < r ? lo : hi) = mid;
  }
  return lo;
}

// TUM monoVO's camera (1280×1024): the angle from the axis at normalised radius r_d is
// θ = atan2(sin ωr_d, 2 tan(ω/2) cos ωr_d) (fov.hpp); the border midpoints sit at
// r_d = (c + 0.5)/f and (w − 0.5 − c)/f, so the figures are closed forms. Its corners are
// ≈ 90.8° off-axis: the diagonal exceeds 180° though no border midpoint reaches 90°.
TEST(FieldOfViewTest, FovModelMatchesTheClosedForm) {
  const double fx = 446.91584, fy = 556.13952, cx = 637.2728, cy = 509.770464, w = 0.934785;
  const Camera camera = Camera::create("fov", vec({fx, fy, cx, cy, w}), 1280, 1024);
  const auto theta = [w](double r_d) {
    return std::atan2(std::sin(w * r_d), 2.0 * std::tan(w / 2.0) * std::cos(w * r_d));
  };
  const double deg = 180.0 / M_PI;
  // acos of the bearing's z near 90° and the bisection-free border points: 1e-9°.
  EXPECT_NEAR(horizontalFovDeg(camera),
              (theta((cx + 0.5) / fx) + theta((1279.5 - cx) / fx)) * deg, 1e-9);
  EXPECT_NEAR(verticalFovDeg(camera),
              (theta((cy + 0.5) / fy) + theta((1023.5 - cy) / fy)) * deg, 1e-9);
  const double corner = std::hypot((cx + 0.5) / fx, (cy + 0.5) / fy);
  EXPECT_GT(theta(corner), M_PI / 2);
  EXPECT_GT(diagonalFovDeg(camera), 180.0);
  EXPECT_DOUBLE_EQ(validPixelFraction(camera), 1.0);  // the image circle r_d = π/ω lies outside
}

TEST(FieldOfViewTest, UnifiedNearXiOneSeesBeyond180Degrees) {
  // The paper's set-up: 480×480, ξ near 1, f ≈ 0.3 w.
  const double xi = 0.98;
  const double f = 144.0;
  const Camera camera = Camera::create("ucm", vec({f, f, 239.5, 239.5, xi}), 480, 480);
  const FieldOfView fov = fieldOfView(camera);
  EXPECT_GT(fov.maximum_deg, 180.0);
  EXPECT_GT(fov.horizontal_deg, 180.0);
  const double deg = 180.0 / M_PI;
  // Border midpoints at r = 240/f, corners at r = 240√2/f; bisection above is exact to 1e-15.
  EXPECT_NEAR(fov.horizontal_deg, 2.0 * ucmAngle(240.0 / f, xi) * deg, 1e-7);
  EXPECT_NEAR(fov.diagonal_deg, 2.0 * ucmAngle(240.0 * std::sqrt(2.0) / f, xi) * deg, 1e-7);
  EXPECT_NEAR(fov.maximum_deg, fov.diagonal_deg, 1e-7);
  EXPECT_DOUBLE_EQ(fov.valid_pixel_fraction, 1.0);  // ξ < 1: every pixel unprojects
}

}  // namespace
}  // namespace omnidso
