// The tracking residual (one relative pose, the target affine free): gradient checks of
// the hand-derived and the autodiff versions for every camera model, agreement with the
// full photometric residual, and coarse-to-fine recovery of a relative pose on rendered
// images (levels 1 then 0).

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/pyramid.hpp"
#include "omnidso/residuals/se3_manifold.hpp"
#include "residuals/residual_test_support.hpp"
#include "residuals/sphere_scene.hpp"

namespace omnidso::test {
namespace {

constexpr int kN = 8;
// Gradient-check settings: residual_test_support.hpp. Analytic vs autodiff to rounding:
constexpr double kResidualAgreement = 1e-9;
constexpr double kJacobianAgreement = 1e-7;

template <typename Tag>
class TrackingResidualTest : public ::testing::Test {};
using Models = ::testing::Types<Pinhole, Ucm, Eucm, Ds, Kb4, Fov>;
TYPED_TEST_SUITE(TrackingResidualTest, Models);

ceres::GradientChecker::ProbeResults probe(const ceres::CostFunction& cost,
                                           const std::array<const double*, 2>& blocks) {
  SE3Manifold se3;
  const std::vector<const ceres::Manifold*> manifolds = {&se3, nullptr};
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = kRiddersInitialStep;
  ceres::GradientChecker checker(&cost, &manifolds, options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(blocks.data(), kGradientCheckPrecision, &results)) << results.error_log;
  return results;
}

TYPED_TEST(TrackingResidualTest, GradientsAndAgreementWithThePhotometricResidual) {
  const ImageF target = smoothTexture(kTestWidth, kTestHeight);
  const auto camera = TypeParam::camera();
  const Eigen::Vector2d centre = TypeParam::params().template segment<2>(2);
  const SE3d T_world_host = poseFrom(0.1, -0.2, 0.3, 0.5, -0.2, 0.1);
  const SE3d T_host_target = poseFrom(0.02, -0.03, 0.01, 0.08, -0.03, 0.05);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (int attempt = 0; attempt < 500 && checked < 4; ++attempt) {
    // A full photometric observation; the tracking one is derived from it.
    PhotometricObservation<kN> obs;
    obs.target_image = &target;
    obs.host_exposure = 1.0;
    obs.target_exposure = 1.3;
    const double radius = 50.0 + 50.0 * unit(rng);  // see photometric_gradient_test.cc
    const double angle = 2.0 * M_PI * unit(rng);
    obs.host.pixel = centre + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    for (int o = 0; o < kN; ++o) {
      obs.host.intensity[o] = 100.0 + 40.0 * unit(rng);
      obs.host.sqrt_weight[o] = 0.5 + 0.5 * unit(rng);
    }
    PhotometricBlocks<TypeParam::kNumParams> blocks;
    blocks.host_pose = poseBlock(T_world_host);
    blocks.target_pose = poseBlock(T_world_host * T_host_target);
    blocks.inverse_distance = 0.2 + 0.8 * unit(rng);
    blocks.host_affine = {0.1, 3.0};
    blocks.target_affine = {-0.05, -2.0};
    blocks.intrinsics = TypeParam::params();
    const auto full_pointers = blocks.pointers();
    if (TypeParam::status(obs, full_pointers.data()) != PhotometricStatus::kValid) continue;
    std::array<Eigen::Vector2d, kN> pixels;
    if (!targetPixels<TypeParam>(obs, blocks, &pixels) ||
        !awayFromCellEdges(pixels, kCellEdgeMargin)) {
      continue;
    }

    auto tracking =
        TypeParam::template trackingObservation<kN>(camera, obs.host, blocks.inverse_distance);
    ASSERT_TRUE(tracking.has_value());
    tracking->target_image = &target;
    tracking->host_exposure = obs.host_exposure;
    tracking->target_exposure = obs.target_exposure;
    tracking->host_a = blocks.host_affine[0];
    tracking->host_b = blocks.host_affine[1];
    const std::array<double, 7> relative = poseBlock(T_host_target.inverse());
    const std::array<const double*, 2> pointers = {relative.data(), blocks.target_affine.data()};

    const std::unique_ptr<ceres::CostFunction> analytic(
        TypeParam::template tracking<kN>(DifferentiationMode::kAnalytic, camera, *tracking));
    const std::unique_ptr<ceres::CostFunction> autodiff(
        TypeParam::template tracking<kN>(DifferentiationMode::kAutodiff, camera, *tracking));
    const auto a = probe(*analytic, pointers);
    const auto b = probe(*autodiff, pointers);
    for (int i = 0; i < kN; ++i) EXPECT_NEAR(a.residuals[i], b.residuals[i], kResidualAgreement);
    for (int k = 0; k < 2; ++k) {
      EXPECT_LE((a.local_jacobians[k] - b.local_jacobians[k]).norm(),
                kJacobianAgreement * b.local_jacobians[k].norm());
    }

    // Same residual as the full photometric one with T_target_host = T_wt⁻¹ T_wh; the
    // relative-pose Jacobian equals the host-pose one (both perturb T_th on the right).
    const std::unique_ptr<ceres::CostFunction> full(
        TypeParam::photometric(DifferentiationMode::kAnalytic, obs));
    std::array<double, kN> r_full;
    ASSERT_TRUE(full->Evaluate(full_pointers.data(), r_full.data(), nullptr));
    for (int i = 0; i < kN; ++i) EXPECT_NEAR(a.residuals[i], r_full[i], kResidualAgreement);
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

// Coarse-to-fine alignment as the coarse tracker does it: level 1, then level 0.
TYPED_TEST(TrackingResidualTest, RecoversRelativePoseOnRenderedImages) {
  const auto camera0 = TypeParam::camera();
  const SE3d T_world_host = poseFrom(0.05, -0.1, 0.08, 0.2, -0.1, 0.05);
  const SE3d T_host_target = poseFrom(0.03, -0.05, 0.02, 0.3, -0.1, 0.2);
  const Photometry host_photometry{1.0, 0.1, 5.0};
  const Photometry target_photometry{1.5, -0.2, -3.0};
  const SphereScene scene;
  const ImagePyramid host(
      scene.render(camera0, T_world_host, kTestWidth, kTestHeight, host_photometry), 2);
  const ImagePyramid target(scene.render(camera0, T_world_host * T_host_target, kTestWidth,
                                         kTestHeight, target_photometry),
                            2);

  const SE3d truth = T_host_target.inverse();  // T_target_host
  Eigen::Matrix<double, 6, 1> start_error;
  start_error << 0.04, -0.03, 0.03, 0.015, -0.01, 0.012;
  std::array<double, 7> relative = poseBlock(truth * SE3d::exp(start_error));
  std::array<double, 2> affine = {target_photometry.a + 0.1, target_photometry.b + 5.0};

  const Eigen::Vector2d centre = TypeParam::params().template segment<2>(2);
  for (int level = 1; level >= 0; --level) {
    typename TypeParam::Params params = TypeParam::params();
    scaleIntrinsicsToLevel(params, level);
    const typename TypeParam::template Camera<double> camera(params);
    SE3Manifold se3;
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    for (int v = 8; v < kTestHeight - 8; v += 10) {
      for (int u = 8; u < kTestWidth - 8; u += 10) {
        const Eigen::Vector2d p0(u, v);
        if ((p0 - centre).norm() > 100.0) continue;
        Eigen::Vector3d bearing;
        if (!camera0.unproject(p0, bearing)) continue;
        const double d = 1.0 / scene.distanceAlong(T_world_host, bearing);
        const HostPatch<kN> patch = makeHostPatch<kN>(
            host.level(level), host.gradients(level),
            Eigen::Vector2d(pixelToLevel(p0.x(), level), pixelToLevel(p0.y(), level)));
        auto obs = TypeParam::template trackingObservation<kN>(camera, patch, d);
        if (!obs) continue;
        obs->target_image = &target.level(level);
        obs->host_exposure = host_photometry.exposure;
        obs->target_exposure = target_photometry.exposure;
        obs->host_a = host_photometry.a;
        obs->host_b = host_photometry.b;
        auto* cost = TypeParam::template tracking<kN>(DifferentiationMode::kAnalytic, camera, *obs);
        std::array<double, kN> r;
        const std::array<const double*, 2> blocks = {relative.data(), affine.data()};
        if (!cost->Evaluate(blocks.data(), r.data(), nullptr)) {  // drop invalid ones
          delete cost;
          continue;
        }
        problem.AddResidualBlock(cost, makePhotometricLoss(kN), relative.data(), affine.data());
      }
    }
    ASSERT_GE(problem.NumResidualBlocks(), 100) << "level " << level;
    problem.SetManifold(relative.data(), &se3);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = 30;
    options.logging_type = ceres::SILENT;  // steps leaving the image are expected
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  }
  // Tolerance: with known inverse distances only the pose and brightness are free; the
  // interpolation error (~0.05 px per residual, see photometric_scene_test.cc) over ~250
  // points leaves the pose within ~1e-3 rad and ~1 cm; bounds keep a factor ~3.
  const Eigen::Matrix<double, 6, 1> e =
      (SE3d::fromParameters(relative.data()).inverse() * truth).log();
  EXPECT_LT(e.tail<3>().norm(), 3e-3) << e.transpose();
  EXPECT_LT(e.head<3>().norm(), 1.5e-2) << e.transpose();
  EXPECT_NEAR(affine[0], target_photometry.a, 1e-2);
  EXPECT_NEAR(affine[1], target_photometry.b, 1.5);
}

}  // namespace
}  // namespace omnidso::test
