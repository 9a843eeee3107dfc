// The initialiser's patches (initializer_level_patches.hpp): their hand-written tangent
// Jacobian ∂r/∂[δ a b d] against numeric differences (ceres::GradientChecker, SE3Manifold on
// the pose), and residual and Jacobian against the Ceres path's cost function
// (PhotometricResidualAnalytic, itself gradient-checked in tests/residuals) mapped to the
// tangent space — the same kernel, so to rounding.
#include <ceres/gradient_checker.h>
#include <ceres/sized_cost_function.h>
#include <gtest/gtest.h>

#include <memory>
#include <omnidso/frontend/initializer_level_patches.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <random>

#include "residuals/residual_test_support.hpp"

namespace omnidso {
namespace {

constexpr int kN = InitializerPatches::kPatchSize;

// One patch as a Ceres cost function over [pose (7), affine (2), d (1)]: the ambient pose
// Jacobian J·P⁺, so that GradientChecker's J_ambient·P is the tangent J.
class PatchCost final : public ceres::SizedCostFunction<kN, 7, 2, 1> {
 public:
  explicit PatchCost(InitializerPatches* patches) : patches_(patches) {}
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    patches_->setPoint(x[0], x[1]);
    InitializerPatches::Residuals r, J_d;
    InitializerPatches::FrameJacobian J_f;
    if (!patches_->evaluate(0, x[2][0], &r, jacobians ? &J_f : nullptr, jacobians ? &J_d : nullptr))
      return false;
    Eigen::Map<InitializerPatches::Residuals>{residuals} = r;
    if (!jacobians) return true;
    if (jacobians[0])
      ambientFromTangentJacobian<kN>(se3TangentToAmbient(x[0]),
                                     Eigen::Matrix<double, kN, 6, Eigen::RowMajor>(J_f.leftCols<6>()),
                                     jacobians[0]);
    if (jacobians[1]) Eigen::Map<Eigen::Matrix<double, kN, 2, Eigen::RowMajor>>{jacobians[1]} = J_f.rightCols<2>();
    if (jacobians[2]) Eigen::Map<InitializerPatches::Residuals>{jacobians[2]} = J_d;
    return true;
  }

 private:
  InitializerPatches* patches_;
};

TEST(InitializerLevelPatchesTest, JacobianMatchesNumericDifferencesAndTheCeresCost) {
  using test::Ucm;
  const ImageF target = test::smoothTexture(test::kTestWidth, test::kTestHeight);
  const std::array<double, 7> host_pose = test::poseBlock(SE3d());
  const std::array<double, 2> host_affine{0.0, 0.0};
  const double frame_exposure = 1.3;
  std::mt19937 rng(7u);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const SE3d frame_pose = test::poseFrom(0.02, -0.03, 0.01, 0.08, -0.03, 0.05);
  int checked = 0;
  for (int attempt = 0; attempt < 1000 && checked < 6; ++attempt) {
    test::PhotometricBlocks<Ucm::kNumParams> blocks;
    blocks.host_pose = host_pose;
    blocks.target_pose = test::poseBlock(frame_pose);
    blocks.inverse_distance = 0.2 + 0.8 * unit(rng);
    blocks.target_affine = {-0.05, -2.0};
    blocks.intrinsics = Ucm::params();
    PhotometricObservation<kN> obs;
    obs.target_image = &target;
    obs.target_exposure = frame_exposure;
    obs.host.pixel = Eigen::Vector2d(60 + 200 * unit(rng), 40 + 160 * unit(rng));
    for (int o = 0; o < kN; ++o) {
      obs.host.intensity[o] = 60.0 + 100.0 * unit(rng);
      obs.host.sqrt_weight[o] = 0.5 + 0.5 * unit(rng);
    }
    std::array<Eigen::Vector2d, kN> pixels;
    if (!test::targetPixels<Ucm>(obs, blocks, &pixels) ||
        !test::awayFromCellEdges(pixels, test::kCellEdgeMargin))
      continue;
    InitializerLevelPatches<UnifiedCamera> patches(Ucm::camera(), 1.0, host_pose.data(),
                                                   host_affine.data(), 1);
    patches.setFrame(target, nullptr, frame_exposure);
    patches.setPoint(blocks.target_pose.data(), blocks.target_affine.data());
    if (!patches.addIfValid(obs.host, blocks.inverse_distance)) continue;
    SCOPED_TRACE(testing::Message() << "pixel " << obs.host.pixel.transpose());

    // Numeric differences.
    const PatchCost cost(&patches);
    static const SE3Manifold se3;
    const std::vector<const ceres::Manifold*> manifolds = {&se3, nullptr, nullptr};
    ceres::NumericDiffOptions numeric;
    numeric.ridders_relative_initial_step_size = test::kRiddersInitialStep;
    ceres::GradientChecker checker(&cost, &manifolds, numeric);
    ceres::GradientChecker::ProbeResults mine;
    const double* x[] = {blocks.target_pose.data(), blocks.target_affine.data(),
                         &blocks.inverse_distance};
    EXPECT_TRUE(checker.Probe(x, test::kGradientCheckPrecision, &mine)) << mine.error_log;

    // The Ceres path's cost function (level 0, the same blocks), in the tangent space.
    const std::unique_ptr<ceres::CostFunction> analytic(
        Ucm::photometric<kN>(DifferentiationMode::kAnalytic, obs));
    const std::vector<const ceres::Manifold*> all = {&se3, &se3, nullptr, nullptr, nullptr, nullptr};
    ceres::GradientChecker analytic_checker(analytic.get(), &all, numeric);
    ceres::GradientChecker::ProbeResults theirs;
    analytic_checker.Probe(blocks.pointers().data(), test::kGradientCheckPrecision, &theirs);
    EXPECT_LT((mine.residuals - theirs.residuals).norm(), 1e-12 * theirs.residuals.norm());
    for (const auto& [k, their_block] : {std::pair{0, 1}, std::pair{1, 4}, std::pair{2, 2}}) {
      const Eigen::MatrixXd& J = theirs.local_jacobians[static_cast<size_t>(their_block)];
      EXPECT_LT((mine.local_jacobians[static_cast<size_t>(k)] - J).norm(), 1e-12 * J.norm())
          << "block " << k << "\nmine\n" << mine.local_jacobians[static_cast<size_t>(k)]
          << "\nthe cost function's\n" << J;
    }
    ++checked;
  }
  EXPECT_EQ(checked, 6);
}

}  // namespace
}  // namespace omnidso
