// A point's residuals as functions of its inverse distance (backend/inverse_distance_residuals.hpp)
// against the window's analytic cost function on the same observation: the same r and ∂r/∂d
// bit for bit (the same kernel on the same inputs — the candidate refinement's results must
// not depend on which of the two it evaluates), and the same verdict where the residual is
// invalid, for every model with a residual kernel.
#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <string>
#include <omnidso/backend/inverse_distance_residuals.hpp>
#include <omnidso/backend/photometric_factory.hpp>
#include <vector>

#include "window_test_scenes.hpp"

namespace omnidso {
namespace {

using test::sweep;
using test::WindowScene;

class InverseDistanceResidualsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(InverseDistanceResidualsTest, EqualTheCostFunctionBitForBit) {
  const Camera camera = synth::syntheticCamera(GetParam(), GetParam() == "pinhole" ? 90.0 : 185.0,
                                               320, 320);
  const int num_keyframes = 4;
  const WindowScene ws(camera, num_keyframes, sweep);
  const auto factory = PhotometricResidualFactory::forModel(camera.modelName());
  const Eigen::VectorXd intrinsics = camera.params();
  std::vector<std::array<double, 7>> poses(num_keyframes);
  std::vector<std::array<double, 2>> affine(num_keyframes);
  for (int k = 0; k < num_keyframes; ++k) {
    ws.poses[k].toParameters(poses[k].data());
    affine[k] = {0.02 * k, -1.5 * k};
  }
  const std::vector<double> exposures = {1.0, 1.3, 0.8, 1.1};
  std::vector<InverseDistanceTarget> targets;
  for (int k = 1; k < num_keyframes; ++k)
    targets.push_back({&ws.images[k]->level(0), ws.images[k]->content(0), poses[k].data(),
                       affine[k].data(), exposures[k]});

  int valid = 0, invalid = 0;
  const Mask mask = validityMask(camera);
  for (const Eigen::Vector2i& pixel : test::gradientPixels(*ws.images[0], mask, 32)) {
    const HostPatch<kWindowPatternSize> host =
        makeHostPatch<kWindowPatternSize>(ws.images[0]->level(0), ws.images[0]->gradients(0),
                                          pixel.cast<double>());
    const auto residuals = factory->makeInverseDistanceResiduals(
        intrinsics, host, poses[0].data(), affine[0].data(), exposures[0], targets);
    ASSERT_EQ(residuals->numTargets(), num_keyframes - 1);
    for (int k = 1; k < num_keyframes; ++k) {
      WindowObservation obs;
      obs.host = host;
      obs.host_exposure = exposures[0];
      obs.target_image = &ws.images[k]->level(0);
      obs.target_content = ws.images[k]->content(0);
      obs.target_exposure = exposures[k];
      const std::unique_ptr<ceres::CostFunction> cost(
          factory->makeCost(DifferentiationMode::kAnalytic, obs));
      // 0.1–10 m, beyond (d = 0) and behind (d < 0: invalid); far targets leave the image.
      for (const double d : {-0.5, 0.0, 0.1, 0.7, 2.0, 10.0}) {
        double d_block = d;
        double* blocks[] = {poses[0].data(), poses[k].data(), &d_block, affine[0].data(),
                            affine[k].data(), const_cast<double*>(intrinsics.data())};
        InverseDistanceResiduals::Patch r_cost, J_cost, r, J;
        double* jacobians[6] = {nullptr, nullptr, J_cost.data(), nullptr, nullptr, nullptr};
        const bool cost_valid = cost->Evaluate(blocks, r_cost.data(), jacobians);
        const bool ok = residuals->evaluate(k - 1, d, &r, &J);
        ASSERT_EQ(ok, cost_valid) << "pixel " << pixel.transpose() << ", target " << k << ", d " << d;
        if (!ok) {
          ++invalid;
          continue;
        }
        ++valid;
        for (int o = 0; o < kWindowPatternSize; ++o) {
          EXPECT_EQ(r[o], r_cost[o]) << "r_" << o;
          EXPECT_EQ(J[o], J_cost[o]) << "∂r_" << o << "/∂d";
        }
      }
    }
  }
  EXPECT_GT(valid, 50);
  EXPECT_GT(invalid, 10);
}

INSTANTIATE_TEST_SUITE_P(Models, InverseDistanceResidualsTest,
                         ::testing::Values("pinhole", "ucm", "eucm", "ds", "kb4", "fov"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace omnidso
