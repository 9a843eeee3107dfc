// The FOV (ATAN) model's own properties (fov.hpp); round trips, Jacobians, float and Jets for
// every model are in camera_model_generic_test.cc.
#include <omnidso/cameras/fov.hpp>
#include <omnidso/cameras/pinhole.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <random>

namespace omnidso {
namespace {

FovCamera<double> fovCamera(double fx, double fy, double cx, double cy, double omega) {
  return FovCamera<double>((FovCamera<double>::VecN() << fx, fy, cx, cy, omega).finished());
}

// Devernay & Faugeras / DSO: r_d = atan(2 r_u tan(ω/2))/ω with r_u = r/z, u = fx (r_d/r_u) x/z
// + cx. At p = (1.2, −1.6, 2), r_u = 1 and (x/z, y/z) = (0.6, −0.8); with ω = 0.9:
//   2 tan(0.45) = 0.966110131233157, atan(0.966110131233157) = 0.768162855754006,
//   r_d = 0.768162855754006/0.9 = 0.853514284171118,
//   u = 400·0.853514284171118·0.6 + 320 = 524.843428201068,
//   v = 420·0.853514284171118·(−0.8) + 240 = −46.7807994814956.
// 15 significant digits of ~500 px leave 1e-12 px; 1e-9 px is rounding-level.
TEST(FovCameraTest, ProjectsByDsosFormulaAtAHandComputedPoint) {
  const FovCamera<double> camera = fovCamera(400, 420, 320, 240, 0.9);
  Eigen::Vector2d uv;
  ASSERT_TRUE(camera.project(Eigen::Vector3d(1.2, -1.6, 2.0), uv));
  EXPECT_NEAR(uv.x(), 524.843428201068, 1e-9);
  EXPECT_NEAR(uv.y(), -46.7807994814956, 1e-9);
  // 90° from the axis (z = 0), where DSO's r_u is infinite: atan2 gives φ = π/2, so
  // r_d = π/(2·0.9) and u = 400·1.74532925199433 + 320 = 1018.13170079773.
  ASSERT_TRUE(camera.project(Eigen::Vector3d(3.0, 0.0, 0.0), uv));
  EXPECT_NEAR(uv.x(), 1018.13170079773, 1e-9);
  EXPECT_NEAR(uv.y(), 240.0, 1e-12);
}

// Beyond 90° the image radius keeps growing (dφ/dθ = k/(cos²θ + k² sin²θ) > 0) up to
// r_d = π/ω straight behind, and every direction round-trips. The round trip's error is
// rounding amplified by the conditioning dθ/dr_d = ωk/E² ≤ ω max(k, 1/k): 1e-12 rad.
TEST(FovCameraTest, PointsBeyondNinetyDegreesRoundTrip) {
  const FovCamera<double> camera = fovCamera(223.5, 260.7, 318.4, 238.7, 0.934785);
  const double k = 2.0 * std::tan(0.934785 / 2.0);
  for (const double theta_deg : {95.0, 120.0, 150.0, 179.0, 179.999}) {
    const double theta = theta_deg * M_PI / 180.0;
    const double azimuth = 0.7;
    const Eigen::Vector3d bearing(std::sin(theta) * std::cos(azimuth),
                                  std::sin(theta) * std::sin(azimuth), std::cos(theta));
    Eigen::Vector2d uv;
    ASSERT_TRUE(camera.project(3.0 * bearing, uv)) << theta_deg;
    const Eigen::Vector2d m((uv.x() - 318.4) / 223.5, (uv.y() - 238.7) / 260.7);
    // r_d from the formula on the unit sphere: atan2(k sin θ, cos θ)/ω.
    EXPECT_NEAR(m.norm(), std::atan2(k * std::sin(theta), std::cos(theta)) / 0.934785, 1e-12);
    Eigen::Vector3d back;
    ASSERT_TRUE(camera.unproject(uv, back)) << theta_deg;
    EXPECT_LT((back - bearing).norm(), 1e-12) << theta_deg;
  }
  // Straight behind is the one direction left out (imaged on the circle r_d = π/ω), and so
  // is every pixel on or beyond that circle.
  Eigen::Vector2d uv;
  EXPECT_FALSE(camera.project(Eigen::Vector3d(0.0, 0.0, -1.0), uv));
  Eigen::Vector3d bearing;
  EXPECT_FALSE(
      camera.unproject(Eigen::Vector2d(318.4 + 223.5 * (M_PI / 0.934785 + 1e-9), 238.7), bearing));
  EXPECT_EQ(camera.maxAngleFromAxis(), M_PI);
}

// ω → 0: k/ω = 2 tan(ω/2)/ω = 1 + ω²/12 + ω⁴/120 and atan y = y − y³/3 + y⁵/5 give
//   r_d = r_u + ω² (r_u/12 − r_u³/3) + ω⁴ (r_u/120 − r_u³/12 + r_u⁵/5) + O(ω⁶).
// At ω = 1e-6 the pixel differs from the pinhole's by at most f ω² r_u (1/12 + r_u²/3): under
// 5e-9 px for r_u ≤ 3. At ω = 1e-3 the difference (up to ~5e-3 px) is the ω² term to within
// the ω⁴ term's size (≤ 3e-8 px), which a wrong k/ω (ω instead of 2 tan(ω/2), say) would
// miss by f r_u ω²/12 ≈ 4e-5 px.
TEST(FovCameraTest, SmallOmegaTendsToThePinhole) {
  const double fx = 500.0, fy = 480.0, cx = 320.0, cy = 240.0;
  const PinholeCamera<double> pinhole(Eigen::Vector4d(fx, fy, cx, cy));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> lateral(-2.1, 2.1);  // r_u ≤ 3
  std::uniform_real_distribution<double> depth(0.5, 20.0);
  for (int i = 0; i < 500; ++i) {
    const double z = depth(rng);
    const Eigen::Vector3d p(lateral(rng) * z, lateral(rng) * z, z);
    const double r_u = std::hypot(p.x(), p.y()) / z;
    Eigen::Vector2d uv_pinhole;
    ASSERT_TRUE(pinhole.project(p, uv_pinhole));
    // 1e-10 px: rounding of ~1e3 px values through atan, tan and a division.
    {
      const double omega = 1e-6;
      Eigen::Vector2d uv;
      ASSERT_TRUE(fovCamera(fx, fy, cx, cy, omega).project(p, uv));
      const double bound = fx * omega * omega * r_u * (1.0 / 12.0 + r_u * r_u / 3.0) + 1e-10;
      EXPECT_LT((uv - uv_pinhole).norm(), bound) << p.transpose();
      // The bearings agree as closely: Δθ = Δ(tan θ)/(1 + r_d²) with the same ω² term.
      Eigen::Vector3d b_fov, b_pinhole;
      ASSERT_TRUE(fovCamera(fx, fy, cx, cy, omega).unproject(uv_pinhole, b_fov));
      ASSERT_TRUE(pinhole.unproject(uv_pinhole, b_pinhole));
      EXPECT_LT((b_fov - b_pinhole).norm(),
                omega * omega * r_u * (1.0 / 12.0 + r_u * r_u / 3.0) / (1.0 + r_u * r_u) + 1e-14);
    }
    {
      const double omega = 1e-3;
      Eigen::Vector2d uv;
      ASSERT_TRUE(fovCamera(fx, fy, cx, cy, omega).project(p, uv));
      const double w2 = omega * omega;
      const Eigen::Vector2d predicted(fx * p.x() / z, fy * p.y() / z);
      const Eigen::Vector2d second_order = predicted * w2 * (1.0 / 12.0 - r_u * r_u / 3.0);
      const double fourth_order = fx * w2 * w2 *
                                  (r_u / 120.0 + std::pow(r_u, 3) / 12.0 + std::pow(r_u, 5) / 5.0);
      EXPECT_LT(((uv - uv_pinhole) - second_order).norm(), fourth_order + 1e-10)
          << p.transpose();
    }
  }
}

// On the exact axis the ratios take their limits (fov.hpp): r_d/r → k/(ω z), sin θ/r_d → ω/k.
// Then ∂u/∂x = fx k/(ω z), ∂b_x/∂u = ω/(k fx), and every ∂/∂ω vanishes with the lateral
// coordinates (u − cx = 0 for any ω; b_z = 1 for any ω). All exact to rounding.
TEST(FovCameraTest, ExactAxisHasTheLimitsAndFiniteJacobians) {
  const double fx = 446.9, fy = 556.1, omega = 0.934785, z = 2.5;
  const FovCamera<double> camera = fovCamera(fx, fy, 637.3, 509.8, omega);
  const double k = 2.0 * std::tan(omega / 2.0);

  Eigen::Vector2d uv;
  FovCamera<double>::Mat23 d_uv_d_p;
  FovCamera<double>::Mat2N d_uv_d_params;
  ASSERT_TRUE(camera.project(Eigen::Vector3d(0.0, 0.0, z), uv, &d_uv_d_p, &d_uv_d_params));
  EXPECT_TRUE(uv == Eigen::Vector2d(637.3, 509.8));
  ASSERT_TRUE(d_uv_d_p.allFinite() && d_uv_d_params.allFinite());
  Eigen::Matrix<double, 2, 3> expected_p;
  expected_p << fx * k / (omega * z), 0, 0, 0, fy * k / (omega * z), 0;
  EXPECT_LT((d_uv_d_p - expected_p).norm(), 1e-12 * expected_p.norm());
  Eigen::Matrix<double, 2, 5> expected_params;
  expected_params << 0, 0, 1, 0, 0, 0, 0, 0, 1, 0;
  EXPECT_LT((d_uv_d_params - expected_params).norm(), 1e-15);

  Eigen::Vector3d bearing;
  FovCamera<double>::Mat32 d_b_d_uv;
  FovCamera<double>::Mat3N d_b_d_params;
  ASSERT_TRUE(camera.unproject(uv, bearing, &d_b_d_uv, &d_b_d_params));
  EXPECT_LT((bearing - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);
  ASSERT_TRUE(d_b_d_uv.allFinite() && d_b_d_params.allFinite());
  Eigen::Matrix<double, 3, 2> expected_uv;
  expected_uv << omega / (k * fx), 0, 0, omega / (k * fy), 0, 0;
  EXPECT_LT((d_b_d_uv - expected_uv).norm(), 1e-12 * expected_uv.norm());
  // fx, fy and ω move nothing at m = 0; cx, cy move it as −u, −v do.
  EXPECT_LT(d_b_d_params.col(0).norm() + d_b_d_params.col(1).norm() + d_b_d_params.col(4).norm(),
            1e-15);
  EXPECT_LT((d_b_d_params.col(2) + d_b_d_uv.col(0)).norm(), 1e-15);
}

// Near the axis (φ < 0.1) the Jacobians use the series of h(φ) = (φ − sin φ cos φ)/φ³; there
// the g m mᵀ term is O(r_d²) and the random points of the generic suite rarely fall, so compare
// the hand-written Jacobians with ceres::Jet's (exact chain rule through atan2, sin, cos) on
// both sides of the switch at 0.1, to 1e-9 relative as the generic Jet tests do.
TEST(FovCameraTest, JacobiansNearTheAxisEqualJetDerivatives) {
  using Jet = ceres::Jet<double, 8>;  // 3 point (or 2 pixel) + 5 parameter directions
  const FovCamera<double> camera = fovCamera(446.9, 556.1, 637.3, 509.8, 0.934785);
  auto jet_camera = camera.cast<Jet>();
  for (int j = 0; j < 5; ++j) jet_camera.params()[j].v[3 + j] = 1.0;
  const auto relative = [](const auto& a, const auto& b) { return (a - b).norm() / a.norm(); };
  for (const double phi : {1e-5, 1e-3, 0.05, 0.0999, 0.1001, 0.3}) {
    // A pixel at normalised radius r_d = φ/ω, off both axes.
    const double r_d = phi / 0.934785;
    const Eigen::Vector2d uv(637.3 + 446.9 * 0.6 * r_d, 509.8 - 556.1 * 0.8 * r_d);
    Eigen::Vector3d bearing;
    FovCamera<double>::Mat32 d_b_d_uv;
    FovCamera<double>::Mat3N d_b_d_params;
    ASSERT_TRUE(camera.unproject(uv, bearing, &d_b_d_uv, &d_b_d_params));
    Eigen::Matrix<Jet, 2, 1> uv_jet(Jet(uv.x(), 0), Jet(uv.y(), 1));
    auto unproject_camera = camera.cast<Jet>();
    for (int j = 0; j < 5; ++j) unproject_camera.params()[j].v[2 + j] = 1.0;
    Eigen::Matrix<Jet, 3, 1> bearing_jet;
    ASSERT_TRUE(unproject_camera.unproject(uv_jet, bearing_jet));
    Eigen::Matrix<double, 3, 7> unproject_jet;
    for (int r = 0; r < 3; ++r) unproject_jet.row(r) = bearing_jet[r].v.head<7>().transpose();
    EXPECT_LT(relative(d_b_d_uv, unproject_jet.leftCols<2>()), 1e-9) << phi;
    EXPECT_LT(relative(d_b_d_params, unproject_jet.rightCols<5>()), 1e-9) << phi;

    const Eigen::Vector3d p = 2.0 * bearing;
    Eigen::Vector2d projected;
    FovCamera<double>::Mat23 d_uv_d_p;
    FovCamera<double>::Mat2N d_uv_d_params;
    ASSERT_TRUE(camera.project(p, projected, &d_uv_d_p, &d_uv_d_params));
    Eigen::Matrix<Jet, 3, 1> p_jet(Jet(p.x(), 0), Jet(p.y(), 1), Jet(p.z(), 2));
    Eigen::Matrix<Jet, 2, 1> projected_jet;
    ASSERT_TRUE(jet_camera.project(p_jet, projected_jet));
    Eigen::Matrix<double, 2, 8> project_jet;
    for (int r = 0; r < 2; ++r) project_jet.row(r) = projected_jet[r].v.transpose();
    EXPECT_LT(relative(d_uv_d_p, project_jet.leftCols<3>()), 1e-9) << phi;
    EXPECT_LT(relative(d_uv_d_params, project_jet.rightCols<5>()), 1e-9) << phi;
  }
}

}  // namespace
}  // namespace omnidso
