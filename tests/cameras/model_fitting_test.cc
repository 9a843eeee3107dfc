// Converting calibrations between camera models (model_fitting.hpp).
#include <gtest/gtest.h>

#include <omnidso/cameras/model_fitting.hpp>
#include <omnidso/core/error.hpp>

#include "vector_literal.hpp"

namespace omnidso {
namespace {

using test::vec;

// Small grids keep the suite fast; the properties do not depend on the density.
FitOptions quickOptions() {
  FitOptions options;
  options.samples_per_axis = 20;
  options.validation_per_axis = 40;
  options.boundary_samples = 90;
  return options;
}

// A fisheye on 480×480 as in the paper's TUM omni set-up.
Camera ucmFisheye() {
  return Camera::create("ucm", vec({300.0, 301.0, 239.2, 240.6, 0.95}), 480, 480);
}

// Largest pixel distance between `source` pixels and the projections of their bearings in
// `target`, over `pixels` — computed here through the public Camera API only.
double maxDeviation(const Camera& source, const Camera& target,
                    const std::vector<Eigen::Vector2d>& pixels) {
  double max_error = 0.0;
  for (const Eigen::Vector2d& uv : pixels) {
    Eigen::Vector3d bearing;
    Eigen::Vector2d back;
    if (!source.unproject(uv, bearing)) continue;
    const bool ok =
        std::visit([&](const auto& m) { return m.project(bearing, back); }, target.model());
    if (ok) max_error = std::max(max_error, (back - uv).norm());
  }
  return max_error;
}

TEST(ModelFittingTest, ConvertingToItselfReproducesTheModel) {
  const std::vector<Camera> cameras = {
      ucmFisheye(),
      Camera::create("kb4", vec({190, 191, 239.5, 240.1, 0.01, -0.005, 0.001, -2e-4}), 480, 480),
      Camera::create("pinhole-radtan", vec({458.6, 457.3, 367.2, 248.4, -0.28, 0.07, 2e-4, 2e-5}),
                     752, 480)};
  for (const Camera& camera : cameras) {
    const FitResult fit = fitCameraModel(camera, camera.modelName(), quickOptions());
    // The start is the solution: only round-trip rounding remains (≪ 1e-6 px).
    EXPECT_LT(fit.max_error_px, 1e-6) << camera.modelName();
    EXPECT_EQ(fit.validation_outside_domain, 0);
    EXPECT_LT((fit.camera.params() - camera.params()).norm(), 1e-6 * camera.params().norm());
  }
}

// EUCM (β = 1) and Double Sphere (ξ = 0) contain UCM exactly (α = ξ/(1+ξ), f_α = f/(1+ξ)),
// so the optimum has zero error; 1e-3 px allows for the solver's stopping tolerance.
TEST(ModelFittingTest, ModelsContainingUcmReproduceIt) {
  const Camera source = ucmFisheye();
  for (const std::string target : {"eucm", "ds"}) {
    const FitResult fit = fitCameraModel(source, target, quickOptions());
    EXPECT_EQ(fit.camera.modelName(), target);
    EXPECT_LT(fit.max_error_px, 1e-3) << target;
    EXPECT_LT(fit.rms_error_px, 1e-3) << target;
    EXPECT_EQ(fit.validation_outside_domain, 0) << target;
    EXPECT_GT(fit.num_samples, 100);
  }
  // The α-form: α = ξ/(1+ξ), fx_α = fx/(1+ξ); the solution is unique, so the fit finds it.
  const FitResult eucm = fitCameraModel(source, "eucm", quickOptions());
  EXPECT_NEAR(eucm.camera.params()[4], 0.95 / 1.95, 1e-5);
  EXPECT_NEAR(eucm.camera.params()[5], 1.0, 1e-4);
  EXPECT_NEAR(eucm.camera.params()[0], 300.0 / 1.95, 1e-3);
}

// UCM cannot represent a Double Sphere with ξ ≠ 0 or a general KB4 exactly: the fit must
// report its error honestly. The reported maximum is the maximum over the validation pixels
// (fitSamplePixels), so an independent computation over the same pixels must give the same
// number (to rounding, 1e-9 px), and it must be clearly non-zero.
TEST(ModelFittingTest, UcmFitToDoubleSphereAndKb4ReportsItsTrueError) {
  const FitOptions options = quickOptions();
  const std::vector<Camera> sources = {
      Camera::create("ds", vec({160.0, 161.0, 239.5, 240.5, -0.25, 0.58}), 480, 480),
      Camera::create("kb4", vec({150.0, 151.0, 239.5, 240.5, 0.08, -0.06, 0.03, -0.01}), 480, 480)};
  for (const Camera& source : sources) {
    const FitResult fit = fitCameraModel(source, "ucm", options);
    const std::vector<Eigen::Vector2d> validation =
        fitSamplePixels(source, options.validation_per_axis, 2 * options.boundary_samples);
    EXPECT_EQ(fit.num_validation, static_cast<int>(validation.size()));
    EXPECT_NEAR(fit.max_error_px, maxDeviation(source, fit.camera, validation), 1e-9)
        << source.modelName();
    EXPECT_GT(fit.max_error_px, 1e-3) << source.modelName();
    EXPECT_LE(fit.rms_error_px, fit.max_error_px);
    // A dense check on every 4th pixel: the validation grid is a good sample of the image, so
    // the true maximum there is at most a few times the reported one (a loose, not a tight,
    // bound: the grid misses the exact worst pixel).
    std::vector<Eigen::Vector2d> dense;
    for (int v = 0; v < source.height(); v += 4) {
      for (int u = 0; u < source.width(); u += 4) {
        if (isValidPixel(source, Eigen::Vector2d(u, v))) dense.emplace_back(u, v);
      }
    }
    EXPECT_LT(maxDeviation(source, fit.camera, dense), 3.0 * fit.max_error_px + 0.1);
  }
}

TEST(ModelFittingTest, PinholeCannotHoldAFisheyeBeyond90Degrees) {
  // UCM ξ = 0.95 on 480×480 with f = 144 sees ≈ 116° off axis at the border midpoints: the
  // pinhole target cannot project those bearings, and the fit says so instead of hiding it.
  const Camera source = Camera::create("ucm", vec({144.0, 144.0, 239.5, 239.5, 0.95}), 480, 480);
  const FitResult fit = fitCameraModel(source, "pinhole", quickOptions());
  EXPECT_GT(fit.validation_outside_domain, 0);
  EXPECT_LT(fit.validation_outside_domain, fit.num_validation);
}

TEST(ModelFittingTest, RejectsUnknownTarget) {
  EXPECT_THROW(fitCameraModel(ucmFisheye(), "spherical-harmonics"), Error);
}

}  // namespace
}  // namespace omnidso
