// Identities between the models: special parameter values turn one model into another.
// The two sides evaluate algebraically equal expressions in a different order, so they
// agree to rounding: 1e-9 px on pixels (≈ 1e4 ulps of a 500-px coordinate), 1e-12 on unit
// bearings and domain angles.

#include "cameras/camera_model_test_utils.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace omnidso {
namespace {

constexpr double kPixelTolerance = 1e-9;
constexpr double kBearingTolerance = 1e-12;

// Random points over the cap of half-angle max_angle, at distances 0.5–20 m.
std::vector<Eigen::Vector3d> randomPoints(double max_angle, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> distance(0.5, 20.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 2000; ++i) {
    points.push_back(test::randomBearing(rng, max_angle) * distance(rng));
  }
  return points;
}

// Same projection (value and ∂uv/∂p) on every point, same unprojection on a pixel grid
// covering the image and beyond, same domain.
template <typename ModelA, typename ModelB>
void expectSameModel(const ModelA& a, const ModelB& b, unsigned seed) {
  EXPECT_NEAR(a.maxAngleFromAxis(), b.maxAngleFromAxis(), kBearingTolerance);
  const double max_angle = std::min(a.maxAngleFromAxis(), M_PI) - test::kBoundaryMargin;
  int projected = 0;
  for (const Eigen::Vector3d& p : randomPoints(max_angle, seed)) {
    Eigen::Vector2d uv_a = Eigen::Vector2d::Zero(), uv_b = Eigen::Vector2d::Zero();
    Eigen::Matrix<double, 2, 3> J_a, J_b;
    const bool valid_a = a.project(p, uv_a, &J_a);
    ASSERT_EQ(valid_a, b.project(p, uv_b, &J_b)) << p.transpose();
    if (!valid_a) continue;
    ++projected;
    EXPECT_LT((uv_a - uv_b).norm(), kPixelTolerance) << p.transpose();
    EXPECT_LT((J_a - J_b).norm(), 1e-9 * J_a.norm()) << p.transpose();
  }
  EXPECT_GT(projected, 1000);
  for (double v = -480.0; v <= 960.0; v += 7.3) {
    for (double u = -480.0; u <= 960.0; u += 7.3) {
      Eigen::Vector3d b_a = Eigen::Vector3d::Zero(), b_b = Eigen::Vector3d::Zero();
      const bool valid_a = a.unproject(Eigen::Vector2d(u, v), b_a);
      const bool valid_b = b.unproject(Eigen::Vector2d(u, v), b_b);
      // On the exact boundary rounding may decide differently; compare where both succeed.
      if (valid_a && valid_b) {
        EXPECT_LT((b_a - b_b).norm(), kBearingTolerance);
      }
    }
  }
}

TEST(CameraModelIdentities, UnifiedWithXiZeroIsPinhole) {
  const PinholeCamera<double> pinhole(Eigen::Vector4d(460.2, 458.7, 321.3, 238.6));
  UnifiedCamera<double>::VecN params;
  params << 460.2, 458.7, 321.3, 238.6, 0.0;
  const UnifiedCamera<double> ucm(params);
  expectSameModel(pinhole, ucm, 1);
  // The intrinsics' Jacobian columns coincide too.
  const Eigen::Vector3d p(0.3, -0.2, 1.7);
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 4> J_pinhole;
  Eigen::Matrix<double, 2, 5> J_ucm;
  ASSERT_TRUE(pinhole.project(p, uv, nullptr, &J_pinhole));
  ASSERT_TRUE(ucm.project(p, uv, nullptr, &J_ucm));
  EXPECT_LT((J_pinhole - J_ucm.leftCols<4>()).norm(), 1e-12);
}

// α-form of UCM (basalt, Kalibr "eucm" family): u = f_α x/(α‖x‖ + (1−α) z) + c_x.
// Dividing numerator and denominator by 1−α gives the ξ-form with ξ = α/(1−α),
// f_ξ = f_α/(1−α); conversely α = ξ/(1+ξ), f_α = f_ξ/(1+ξ).
TEST(CameraModelIdentities, UnifiedXiAndAlphaFormsAgree) {
  for (const double xi : {0.4, 0.95, 1.5}) {
    SCOPED_TRACE(xi);
    UnifiedCamera<double>::VecN params;
    params << 190.3, 189.7, 240.6, 239.2, xi;
    const UnifiedCamera<double> ucm(params);
    const double alpha = xi / (1.0 + xi);
    const double fx_a = params[0] / (1.0 + xi);
    const double fy_a = params[1] / (1.0 + xi);
    const UnifiedCamera<double> from_alpha =
        unifiedFromAlphaForm(fx_a, fy_a, params[2], params[3], alpha);
    EXPECT_LT((from_alpha.params() - params).norm(), 1e-12 * params.norm());
    std::mt19937 rng(3);
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector3d p =
          test::randomBearing(rng, ucm.maxAngleFromAxis() - test::kBoundaryMargin) * 3.0;
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      ASSERT_TRUE(ucm.project(p, uv));
      const double denominator = alpha * p.norm() + (1.0 - alpha) * p.z();
      const Eigen::Vector2d uv_alpha(fx_a * p.x() / denominator + params[2],
                                     fy_a * p.y() / denominator + params[3]);
      EXPECT_LT((uv - uv_alpha).norm(), kPixelTolerance);
    }
  }
}

TEST(CameraModelIdentities, DoubleSphereWithXiZeroIsUnifiedAlphaForm) {
  // Both branches of the domain: α ≤ ½ (D > 0 binds) and α > ½ (the fold binds).
  for (const double alpha : {0.35, 0.59}) {
    SCOPED_TRACE(alpha);
    DoubleSphereCamera<double>::VecN params;
    params << 150.2, 149.8, 240.1, 239.3, 0.0, alpha;
    expectSameModel(DoubleSphereCamera<double>(params),
                    unifiedFromAlphaForm(150.2, 149.8, 240.1, 239.3, alpha), 5);
  }
}

TEST(CameraModelIdentities, ExtendedUnifiedWithBetaOneIsUnifiedAlphaForm) {
  for (const double alpha : {0.35, 0.62}) {
    SCOPED_TRACE(alpha);
    ExtendedUnifiedCamera<double>::VecN params;
    params << 175.4, 175.1, 240.3, 239.6, alpha, 1.0;
    expectSameModel(ExtendedUnifiedCamera<double>(params),
                    unifiedFromAlphaForm(175.4, 175.1, 240.3, 239.6, alpha), 7);
  }
}

// Double Sphere with α = 0 is UCM with its ξ (the second sphere degenerates to a pinhole).
TEST(CameraModelIdentities, DoubleSphereWithAlphaZeroIsUnified) {
  for (const double xi : {0.3, 0.6}) {
    SCOPED_TRACE(xi);
    DoubleSphereCamera<double>::VecN ds_params;
    ds_params << 150.2, 149.8, 240.1, 239.3, xi, 0.0;
    UnifiedCamera<double>::VecN ucm_params;
    ucm_params << 150.2, 149.8, 240.1, 239.3, xi;
    expectSameModel(DoubleSphereCamera<double>(ds_params), UnifiedCamera<double>(ucm_params),
                    9);
  }
}

}  // namespace
}  // namespace omnidso
