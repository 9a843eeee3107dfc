// One typed suite over every camera model: round trips, Jacobians against central
// differences, float and ceres::Jet instantiations, validity that is never NaN.

#include "cameras/camera_model_test_utils.hpp"

#include <ceres/jet.h>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <type_traits>

namespace omnidso {
namespace {

using test::TestCamera;

template <typename Model>
class CameraModelTest : public ::testing::Test {
 protected:
  std::vector<TestCamera<Model>> cameras_ = test::realisticCameras<Model>();
};

using ModelTypes = test::TupleToTypes<AllCameraModels>::type;
TYPED_TEST_SUITE(CameraModelTest, ModelTypes);

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Every pixel centre of the image: unproject to a unit bearing, project back. In double the
// round trip is exact up to rounding amplified by the model's conditioning, far below 1e-9 px.
TYPED_TEST(CameraModelTest, PixelRoundTripOverWholeImage) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    int valid = 0, behind = 0;
    double worst = 0.0;
    for (int v = 0; v < tc.height; ++v) {
      for (int u = 0; u < tc.width; ++u) {
        const Eigen::Vector2d uv(u, v);
        Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
        if (!tc.camera.unproject(uv, bearing)) continue;
        ++valid;
        behind += bearing.z() < 0.0;
        ASSERT_NEAR(bearing.norm(), 1.0, 1e-12) << uv.transpose();
        Eigen::Vector2d back = Eigen::Vector2d::Zero();
        ASSERT_TRUE(tc.camera.project(bearing, back)) << uv.transpose();
        worst = std::max(worst, (back - uv).norm());
      }
    }
    EXPECT_LT(worst, 1e-9);
    // Not vacuous: the realistic cameras see at least a third of their image (UCM with
    // ξ > 1 has 44% inside the fold).
    EXPECT_GT(valid, tc.width * tc.height / 3);
    if constexpr (std::is_same_v<TypeParam, UnifiedCamera<double>>) {
      // UCM with ξ > 1 sees beyond 180°: some pixels image rays from behind the camera.
      if (tc.camera.xi() > 1.0) {
        EXPECT_GT(behind, 0);
      }
    }
  }
}

// unproject ∘ project on random valid bearings recovers the bearing (1e-9 rad).
TYPED_TEST(CameraModelTest, BearingRoundTrip) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    double worst = 0.0;
    for (const Eigen::Vector3d& p : test::randomValidPoints(tc, 2000, 7)) {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      ASSERT_TRUE(tc.camera.project(p, uv));
      Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
      ASSERT_TRUE(tc.camera.unproject(uv, bearing)) << uv.transpose();
      worst = std::max(worst, angleBetween(bearing, p.normalized()));
    }
    EXPECT_LT(worst, 1e-9);
  }
}

// The boundary of the domain is where maxAngleFromAxis() says.
TYPED_TEST(CameraModelTest, DomainEndsAtMaxAngle) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const double max_angle = tc.camera.maxAngleFromAxis();
    for (double phi = 0.0; phi < 2 * M_PI; phi += 0.5) {
      const auto ray = [&](double theta) {
        return Eigen::Vector3d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
      };
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      EXPECT_TRUE(tc.camera.project(ray(max_angle - 1e-3), uv));
      if (max_angle < M_PI - 1e-3) {
        EXPECT_FALSE(tc.camera.project(ray(max_angle + 1e-3), uv));
      }
    }
  }
}

// Inside the domain the image radius grows with the angle from the axis: the domain
// conditions (derived per model) stop exactly where the image would fold back.
TYPED_TEST(CameraModelTest, ImageRadiusGrowsUpToMaxAngle) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const Eigen::Vector2d centre = tc.camera.params().template segment<2>(2);
    const double end = std::min(static_cast<double>(tc.camera.maxAngleFromAxis()), M_PI) - 1e-3;
    for (double phi = 0.1; phi < 2 * M_PI; phi += 0.7) {
      double previous = -1.0;
      for (int i = 0; i <= 2000; ++i) {
        const double theta = end * i / 2000.0;
        const Eigen::Vector3d ray(std::sin(theta) * std::cos(phi),
                                  std::sin(theta) * std::sin(phi), std::cos(theta));
        Eigen::Vector2d uv = Eigen::Vector2d::Zero();
        ASSERT_TRUE(tc.camera.project(ray, uv)) << "theta " << theta;
        const double radius = (uv - centre).norm();
        ASSERT_GT(radius, previous) << "theta " << theta << " phi " << phi;
        previous = radius;
      }
    }
  }
}

// Validity is a definite answer everywhere: valid results are finite, the origin is invalid.
TYPED_TEST(CameraModelTest, ValidityIsNeverNaN) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    EXPECT_FALSE(tc.camera.project(Eigen::Vector3d::Zero(), uv));
    for (double theta = 0.0; theta <= M_PI; theta += M_PI / 64) {
      for (double phi = 0.0; phi < 2 * M_PI; phi += M_PI / 16) {
        const Eigen::Vector3d p(std::sin(theta) * std::cos(phi),
                                std::sin(theta) * std::sin(phi), std::cos(theta));
        if (tc.camera.project(p, uv)) {
          EXPECT_TRUE(uv.allFinite()) << p.transpose();
        }
      }
    }
    for (int v = -2 * tc.height; v <= 3 * tc.height; v += 16) {
      for (int u = -2 * tc.width; u <= 3 * tc.width; u += 16) {
        Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
        if (tc.camera.unproject(Eigen::Vector2d(u, v), bearing)) {
          EXPECT_TRUE(bearing.allFinite());
          EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
        }
      }
    }
  }
}

// Test points for Jacobians: random valid points plus the optical axis, where several
// models use limits (KB4's θd/r → 1/z).
template <typename Model>
std::vector<Eigen::Vector3d> jacobianTestPoints(const TestCamera<Model>& tc) {
  std::vector<Eigen::Vector3d> points =
      test::randomValidPoints(tc, 200, 11, test::kJacobianBoundaryMargin);
  points.emplace_back(0.0, 0.0, 2.0);
  points.emplace_back(1e-9, -2e-9, 1.5);
  return points;
}

// Hand-written Jacobians of project against central differences (relative 1e-6; the
// difference scheme's own error is ~1e-10, see numericJacobian).
TYPED_TEST(CameraModelTest, ProjectJacobiansMatchCentralDifferences) {
  constexpr int N = TypeParam::kNumParams;
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const TypeParam& cam = tc.camera;
    for (const Eigen::Vector3d& p : jacobianTestPoints(tc)) {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      Eigen::Matrix<double, 2, 3> d_uv_d_p;
      Eigen::Matrix<double, 2, N> d_uv_d_params;
      ASSERT_TRUE(cam.project(p, uv, &d_uv_d_p, &d_uv_d_params));
      Eigen::Vector2d uv_plain = Eigen::Vector2d::Zero();
      cam.project(p, uv_plain);
      EXPECT_TRUE(uv == uv_plain);  // Jacobians must not change the value.
      const auto numeric_p = test::numericJacobian<2, 3>(
          [&](const Eigen::Vector3d& x, Eigen::Vector2d& out) { return cam.project(x, out); },
          p, test::jacobianSteps(p, d_uv_d_p, test::kPixelOutputStep));
      const auto numeric_params = test::numericJacobian<2, N>(
          [&](const Eigen::Matrix<double, N, 1>& x, Eigen::Vector2d& out) {
            return TypeParam(x).project(p, out);
          },
          cam.params(),
          test::jacobianSteps(cam.params(), d_uv_d_params, test::kPixelOutputStep));
      EXPECT_LT(test::columnRelativeError(d_uv_d_p, numeric_p), 1e-6) << p.transpose();
      EXPECT_LT(test::columnRelativeError(d_uv_d_params, numeric_params), 1e-6)
          << p.transpose();
    }
  }
}

TYPED_TEST(CameraModelTest, UnprojectJacobiansMatchCentralDifferences) {
  constexpr int N = TypeParam::kNumParams;
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const TypeParam& cam = tc.camera;
    std::vector<Eigen::Vector2d> pixels = {cam.params().template head<4>().template tail<2>()};
    for (const Eigen::Vector3d& p :
         test::randomValidPoints(tc, 200, 13, test::kJacobianBoundaryMargin)) {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      cam.project(p, uv);
      pixels.push_back(uv);
    }
    for (const Eigen::Vector2d& uv : pixels) {
      Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
      Eigen::Matrix<double, 3, 2> d_b_d_uv;
      Eigen::Matrix<double, 3, N> d_b_d_params;
      ASSERT_TRUE(cam.unproject(uv, bearing, &d_b_d_uv, &d_b_d_params));
      const auto numeric_uv = test::numericJacobian<3, 2>(
          [&](const Eigen::Vector2d& x, Eigen::Vector3d& out) { return cam.unproject(x, out); },
          uv, test::jacobianSteps(uv, d_b_d_uv, test::kBearingOutputStep));
      const auto numeric_params = test::numericJacobian<3, N>(
          [&](const Eigen::Matrix<double, N, 1>& x, Eigen::Vector3d& out) {
            return TypeParam(x).unproject(uv, out);
          },
          cam.params(),
          test::jacobianSteps(cam.params(), d_b_d_params, test::kBearingOutputStep));
      EXPECT_LT(test::columnRelativeError(d_b_d_uv, numeric_uv), 1e-6) << uv.transpose();
      EXPECT_LT(test::columnRelativeError(d_b_d_params, numeric_params), 1e-6)
          << uv.transpose();
    }
  }
}

// The float instantiation round-trips at float precision: a 640-px coordinate carries
// 640·6e-8 ≈ 4e-5 px of rounding, amplified by the chain of ~10–50 operations; 5e-3 px is
// ~100 ulps of the largest coordinate.
TYPED_TEST(CameraModelTest, FloatInstantiationRoundTrip) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const auto cam = tc.camera.template cast<float>();
    int valid = 0;
    float worst = 0.0f;
    for (int v = 0; v < tc.height; v += 4) {
      for (int u = 0; u < tc.width; u += 4) {
        const Eigen::Vector2f uv(u, v);
        Eigen::Vector3f bearing = Eigen::Vector3f::Zero();
        if (!cam.unproject(uv, bearing)) continue;
        Eigen::Vector2f back = Eigen::Vector2f::Zero();
        if (!cam.project(bearing, back)) continue;  // float may differ on the very boundary
        ++valid;
        worst = std::max(worst, (back - uv).norm());
      }
    }
    EXPECT_GT(valid, tc.width * tc.height / 16 / 3);  // a third of the grid
    EXPECT_LT(worst, 5e-3f);
  }
}

// ceres::Jet instantiation: same values as double, and its derivatives equal the
// hand-written Jacobians (both exact up to rounding: 1e-9 relative).
TYPED_TEST(CameraModelTest, JetProjectMatchesHandWritten) {
  constexpr int N = TypeParam::kNumParams;
  using Jet = ceres::Jet<double, 3 + N>;
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    auto jet_cam = tc.camera.template cast<Jet>();
    for (int j = 0; j < N; ++j) jet_cam.params()[j].v[3 + j] = 1.0;
    for (const Eigen::Vector3d& p : test::randomValidPoints(tc, 100, 17)) {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      Eigen::Matrix<double, 2, 3> d_uv_d_p;
      Eigen::Matrix<double, 2, N> d_uv_d_params;
      ASSERT_TRUE(tc.camera.project(p, uv, &d_uv_d_p, &d_uv_d_params));
      Eigen::Matrix<Jet, 3, 1> p_jet;
      for (int i = 0; i < 3; ++i) p_jet[i] = Jet(p[i], i);
      Eigen::Matrix<Jet, 2, 1> uv_jet;
      ASSERT_TRUE(jet_cam.project(p_jet, uv_jet));
      Eigen::Matrix<double, 2, 3 + N> jet_jacobian;
      for (int r = 0; r < 2; ++r) {
        EXPECT_NEAR(uv_jet[r].a, uv[r], 1e-12 * std::abs(uv[r]) + 1e-12);
        jet_jacobian.row(r) = uv_jet[r].v.transpose();
      }
      EXPECT_LT(test::columnRelativeError(d_uv_d_p, jet_jacobian.template leftCols<3>()), 1e-9);
      EXPECT_LT(test::columnRelativeError(d_uv_d_params, jet_jacobian.template rightCols<N>()),
                1e-9);
    }
  }
}

TYPED_TEST(CameraModelTest, JetUnprojectMatchesHandWritten) {
  constexpr int N = TypeParam::kNumParams;
  using Jet = ceres::Jet<double, 2 + N>;
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    auto jet_cam = tc.camera.template cast<Jet>();
    for (int j = 0; j < N; ++j) jet_cam.params()[j].v[2 + j] = 1.0;
    for (const Eigen::Vector3d& p : test::randomValidPoints(tc, 100, 19)) {
      Eigen::Vector2d uv = Eigen::Vector2d::Zero();
      tc.camera.project(p, uv);
      Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
      Eigen::Matrix<double, 3, 2> d_b_d_uv;
      Eigen::Matrix<double, 3, N> d_b_d_params;
      ASSERT_TRUE(tc.camera.unproject(uv, bearing, &d_b_d_uv, &d_b_d_params));
      const Eigen::Matrix<Jet, 2, 1> uv_jet(Jet(uv.x(), 0), Jet(uv.y(), 1));
      Eigen::Matrix<Jet, 3, 1> bearing_jet;
      ASSERT_TRUE(jet_cam.unproject(uv_jet, bearing_jet));
      Eigen::Matrix<double, 3, 2 + N> jet_jacobian;
      for (int r = 0; r < 3; ++r) {
        EXPECT_NEAR(bearing_jet[r].a, bearing[r], 1e-12);
        jet_jacobian.row(r) = bearing_jet[r].v.transpose();
      }
      EXPECT_LT(test::columnRelativeError(d_b_d_uv, jet_jacobian.template leftCols<2>()), 1e-9);
      EXPECT_LT(test::columnRelativeError(d_b_d_params, jet_jacobian.template rightCols<N>()),
                1e-9);
    }
  }
}

// The distortion functor on its own: undistort inverts distort to rounding. distort is
// evaluated with error ~ε|md| and the inverse's condition number ‖(∂md/∂m)⁻¹‖ is below 3
// for |m| ≤ 1.5 with EuRoC's coefficients, so 1e-14 is a few ulps of |m|.
TEST(RadTanDistortion, UndistortInvertsDistortAndJacobiansMatch) {
  const RadTanDistortion<double> radtan(
      Eigen::Vector4d(-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05));
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d m(coordinate(rng), coordinate(rng));
    Eigen::Matrix2d d_md_d_m;
    Eigen::Matrix<double, 2, 4> d_md_d_params;
    const Eigen::Vector2d md = radtan.distort(m, &d_md_d_m, &d_md_d_params);
    Eigen::Vector2d undistorted = Eigen::Vector2d::Zero();
    Eigen::Matrix2d d_m_d_md;
    ASSERT_TRUE(radtan.undistort(md, undistorted, &d_m_d_md));
    EXPECT_LT((undistorted - m).norm(), 1e-14);
    EXPECT_LT((d_m_d_md * d_md_d_m - Eigen::Matrix2d::Identity()).norm(), 1e-12);
    const auto numeric_m = test::numericJacobian<2, 2>(
        [&](const Eigen::Vector2d& x, Eigen::Vector2d& out) {
          out = radtan.distort(x);
          return true;
        },
        m, test::jacobianSteps(m, d_md_d_m, 1e-4));
    const Eigen::Vector4d params = radtan.params();
    const auto numeric_params = test::numericJacobian<2, 4>(
        [&](const Eigen::Vector4d& x, Eigen::Vector2d& out) {
          out = RadTanDistortion<double>(x).distort(m);
          return true;
        },
        params, test::jacobianSteps(params, d_md_d_params, 1e-4));
    EXPECT_LT(test::columnRelativeError(d_md_d_m, numeric_m), 1e-6);
    EXPECT_LT(test::columnRelativeError(d_md_d_params, numeric_params), 1e-6);
  }
}

}  // namespace
}  // namespace omnidso
