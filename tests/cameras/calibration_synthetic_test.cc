// Calibration on synthetic boards: corners of an 8×6 board projected through known
// parameters and poses, then calibrated from nothing (calibrateModels runs the equidistant
// start, the KB4 reference and the model's own adjustment).
//   • without noise the parameters come back to 1e-6 relative (the adjustment converges to
//     the exact minimum, residuals 0);
//   • with 0.3 px Gaussian noise every parameter lies within 3 reported standard deviations.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/cameras/calibration/calibration.hpp>
#include <omnidso/cameras/calibration/initial_estimate.hpp>
#include <random>

namespace omnidso {
namespace {

struct SyntheticCase {
  std::string model;
  std::vector<double> params;
  double max_view_angle_deg;  // board centres up to this angle from the optical axis
};

std::ostream& operator<<(std::ostream& os, const SyntheticCase& c) { return os << c.model; }

constexpr int kWidth = 1280, kHeight = 800;

Camera cameraOf(const SyntheticCase& c) {
  return Camera::create(c.model, Eigen::Map<const Eigen::VectorXd>(
                                     c.params.data(), static_cast<long>(c.params.size())),
                        kWidth, kHeight);
}

// Board poses on a 5 × 4 grid of directions up to max_view_angle_deg, each tilted by ±25°
// about an axis in the board plane, 0.5 m away; views with a corner outside the image or
// the model's domain are skipped.
BoardDetections syntheticViews(const Camera& camera, const BoardSpec& board, double max_deg,
                               double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  BoardDetections d{kWidth, kHeight, {}, {}};
  const Eigen::Vector3d centre_board((board.cols - 1) * board.square / 2,
                                     (board.rows - 1) * board.square / 2, 0);
  for (int i = 0; i < 20; ++i) {
    const double az = 2 * M_PI * (i % 5) / 5.0 + 0.3 * (i / 5);
    const double el = max_deg * M_PI / 180.0 * (0.15 + 0.85 * (i / 5) / 3.0);
    const Eigen::Vector3d dir(std::sin(el) * std::cos(az), std::sin(el) * std::sin(az),
                              std::cos(el));
    // Board z axis facing the camera (−dir), then a tilt about the board's own x or y axis.
    const Eigen::Vector3d z = -dir;
    const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
    Eigen::Matrix3d R;
    R << x, z.cross(x), z;
    const double tilt = (i % 2 ? 25.0 : -25.0) * M_PI / 180.0;
    R = R * Eigen::AngleAxisd(tilt, i % 3 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
                .toRotationMatrix();
    const SE3d T(R, Eigen::Vector3d(0.5 * dir - R * centre_board));
    BoardView view{"view" + std::to_string(i), {}};
    for (int k = 0; k < board.numCorners(); ++k) {
      Eigen::Vector2d uv;
      if (!camera.project(T * board.corner(k), uv)) break;
      view.corners.push_back(uv + Eigen::Vector2d(noise(rng), noise(rng)));
    }
    if (static_cast<int>(view.corners.size()) == board.numCorners()) d.views.push_back(view);
  }
  return d;
}

class CalibrationSyntheticTest : public ::testing::TestWithParam<SyntheticCase> {};

TEST_P(CalibrationSyntheticTest, RecoversExactParametersWithoutNoise) {
  const Camera truth = cameraOf(GetParam());
  const BoardSpec board{8, 6, 0.04};
  const BoardDetections d = syntheticViews(truth, board, GetParam().max_view_angle_deg, 0.0, 1);
  ASSERT_GE(d.views.size(), 10u);
  const CalibrationReport r = calibrateModels(d, board, {GetParam().model});
  const ModelCalibration& m = r.models.at(0);
  EXPECT_EQ(r.selection.numViews(), static_cast<int>(d.views.size()));
  EXPECT_LT(m.rms_px, 1e-6) << m.fit.iterations << " iterations, converged " << m.fit.converged;
  const Eigen::VectorXd p = m.fit.camera.params();
  const Eigen::VectorXd expected = truth.params();
  for (int i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p[i], expected[i], 1e-6 * std::abs(expected[i]))
        << truth.paramNames()[static_cast<size_t>(i)];
  }
}

TEST_P(CalibrationSyntheticTest, ErrorsLieWithinThreeReportedStdDevsWithNoise) {
  const Camera truth = cameraOf(GetParam());
  const BoardSpec board{8, 6, 0.04};
  const BoardDetections d = syntheticViews(truth, board, GetParam().max_view_angle_deg, 0.3, 7);
  const CalibrationReport r = calibrateModels(d, board, {GetParam().model});
  const ModelCalibration& m = r.models.at(0);
  // σ̂ estimates the per-component noise of 0.3 px (≈ 1900 residuals: ±5 % at 3σ).
  EXPECT_NEAR(m.fit.noise_sigma_px, 0.3, 0.03);
  ASSERT_EQ(m.fit.param_stddev.size(), truth.params().size());
  const Eigen::VectorXd error = m.fit.camera.params() - truth.params();
  for (int i = 0; i < error.size(); ++i) {
    EXPECT_GT(m.fit.param_stddev[i], 0.0);
    EXPECT_LT(std::abs(error[i]), 3.0 * m.fit.param_stddev[i])
        << truth.paramNames()[static_cast<size_t>(i)];
  }
}

// Double Sphere with fx 350 on boards up to 60°: the cost has a second basin at ξ ≈ 0.39,
// fx ≈ 606 (RMS 0.016 px without noise) that every start converted from the reference falls
// into; the starts along the ξ–focal valley (calibration.hpp, step 4) reach the true one.
// With 0.3 px noise these boards no longer decide between the two basins (the noisy cost is
// lower at ξ ≈ 0.44 than at the truth), hence no noisy case for this lens.
TEST(CalibrationSyntheticValleyTest, DoubleSphereAcrossTheXiFocalValley) {
  const SyntheticCase lens{"ds", {350.0, 349.2, 641.1, 399.4, -0.2, 0.58}, 60};
  const Camera truth = cameraOf(lens);
  const BoardSpec board{8, 6, 0.04};
  const BoardDetections d = syntheticViews(truth, board, lens.max_view_angle_deg, 0.0, 1);
  const ModelCalibration m = calibrateModels(d, board, {"ds"}).models.at(0);
  EXPECT_LT(m.rms_px, 1e-6);
  const Eigen::VectorXd p = m.fit.camera.params();
  for (int i = 0; i < p.size(); ++i) EXPECT_NEAR(p[i], truth.params()[i], 1e-6 * std::abs(truth.params()[i]));
}

// ceres::Covariance builds its Jacobian with the parameter blocks in address order, so the
// standard deviations followed the heap (last digits differed between runs) until every
// block lived in one buffer (board_adjustment.cc). Solves in one process, with the heap in
// different states in between, must agree bit for bit.
TEST(CalibrationDeterminismTest, SameResultBitForBitWhateverTheHeapLayout) {
  const Camera truth = cameraOf({"kb4", {558.5, 560.5, 620.5, 381.9, -0.0015, -0.0033, 0.0061, -0.0037}, 60});
  const BoardSpec board{8, 6, 0.04};
  const BoardDetections d = syntheticViews(truth, board, 60, 0.3, 7);
  const CornerSelection all = CornerSelection::all(d);
  const InitialCalibration start = initialEquidistantCalibration(d, board);
  const BoardAdjustment first = adjustBoards(d, board, all, start.camera, start.T_camera_board);
  std::vector<std::vector<double>> ballast;
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 50; ++k) ballast.emplace_back(static_cast<size_t>(6 + 13 * k + i));
    const BoardAdjustment again = adjustBoards(d, board, all, start.camera, start.T_camera_board);
    ASSERT_EQ(again.param_stddev.size(), first.param_stddev.size());
    EXPECT_TRUE(again.camera.params() == first.camera.params()) << i;
    EXPECT_TRUE(again.param_stddev == first.param_stddev) << i;
    EXPECT_EQ(again.sum_squared_px, first.sum_squared_px) << i;
  }
}

INSTANTIATE_TEST_SUITE_P(
    EveryModel, CalibrationSyntheticTest,
    ::testing::Values(
        SyntheticCase{"ucm", {500.0, 498.0, 638.2, 402.5, 0.9}, 60},
        SyntheticCase{"eucm", {380.0, 379.0, 640.3, 398.7, 0.6, 1.1}, 60},
        // fx 300 rather than 350: with 0.3 px noise the boards of a 350 px lens (up to 60°)
        // do not decide ξ (see DoubleSphereAcrossTheXiFocalValley below).
        SyntheticCase{"ds", {300.0, 299.2, 641.1, 399.4, -0.2, 0.58}, 60},
        SyntheticCase{"kb4", {558.5, 560.5, 620.5, 381.9, -0.0015, -0.0033, 0.0061, -0.0037}, 60},
        // TUM monoVO's relative calibration on this 1280×800 image.
        SyntheticCase{"fov", {446.9, 434.5, 637.3, 398.1, 0.934785}, 60},
        SyntheticCase{"ucm-radtan",
                      {408.9, 410.5, 630.3, 431.9, 1.05, -0.0083, 0.0118, 0.0023, -0.0042},
                      60},
        SyntheticCase{"pinhole-radtan",
                      {620.0, 618.5, 640.2, 400.6, -0.28, 0.07, 0.0005, -0.0003}, 35},
        SyntheticCase{"pinhole", {620.0, 618.5, 640.2, 400.6}, 35}),
    [](const ::testing::TestParamInfo<SyntheticCase>& info) {
      std::string name = info.param.model;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

}  // namespace
}  // namespace omnidso
