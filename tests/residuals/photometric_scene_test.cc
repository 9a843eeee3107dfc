// Photometric residuals on images rendered from a known scene (sphere_scene.hpp), for every
// camera model, on pyramid levels 0 and 1: the cost at ground truth is at its minimum —
// perturbing any parameter block raises it — and a small Ceres problem recovers the
// ground truth from a perturbed start.

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/image_ops.hpp"
#include "omnidso/core/pyramid.hpp"
#include "omnidso/residuals/se3_manifold.hpp"
#include "residuals/residual_test_support.hpp"
#include "residuals/sphere_scene.hpp"

namespace omnidso::test {
namespace {

constexpr int kN = 8;
// Recovery tolerances. The rendered images are exact only at pixel centres: bilinear
// interpolation of the texture errs by up to h²/8·|I''| ≈ 0.1–0.5 intensity units, and the
// pattern assumes one inverse distance for 8 pixels of a curved surface. With gradients of
// ~3 units/px that is ~0.05 px per residual; over ~200 points it leaves the target pose
// within ~1e-3 rad (0.05 px at f ≈ 90 px) and ~1 cm of the 37 cm baseline, the brightness
// offset within ~0.5 units and the inverse distances within ~0.5 % (median); the bounds
// below keep a factor 2–3 above the worst case observed over all models and levels.
constexpr double kMaxRotationError = 3e-3;       // rad
constexpr double kMaxTranslationError = 1.5e-2;  // m, world scale (baseline 0.37 m)
constexpr double kMaxAffineAError = 1e-2;
constexpr double kMaxAffineBError = 1.5;  // intensity units
constexpr double kMaxMedianInverseDistanceError = 0.02;

// All parameter values of the two-frame problem.
template <int K>
struct State {
  std::array<double, 7> host_pose;
  std::array<double, 7> target_pose;
  std::vector<double> inverse_distances;
  std::array<double, 2> host_affine;
  std::array<double, 2> target_affine;
  Eigen::Matrix<double, K, 1> intrinsics;
};

template <typename Tag>
class PhotometricSceneTest : public ::testing::Test {
 protected:
  static constexpr int K = Tag::kNumParams;

  // Renders host and target frames and creates residuals for a grid of host pixels within
  // 100 px of the principal point (inside every model's image circle), on `level`.
  void setUp(int level) {
    const auto camera = Tag::camera();
    const SE3d T_world_host = poseFrom(0.05, -0.1, 0.08, 0.2, -0.1, 0.05);
    const SE3d T_host_target = poseFrom(0.03, -0.05, 0.02, 0.3, -0.1, 0.2);
    const Photometry host_photometry{1.0, 0.1, 5.0};
    const Photometry target_photometry{1.5, -0.2, -3.0};
    const SphereScene scene;
    host_pyramid_ = std::make_unique<ImagePyramid>(
        scene.render(camera, T_world_host, kTestWidth, kTestHeight, host_photometry), 2);
    target_pyramid_ =
        std::make_unique<ImagePyramid>(scene.render(camera, T_world_host * T_host_target,
                                                    kTestWidth, kTestHeight, target_photometry),
                                       2);

    truth_.host_pose = poseBlock(T_world_host);
    truth_.target_pose = poseBlock(T_world_host * T_host_target);
    truth_.host_affine = {host_photometry.a, host_photometry.b};
    truth_.target_affine = {target_photometry.a, target_photometry.b};
    truth_.intrinsics = Tag::params();
    truth_.inverse_distances.clear();
    observations_.clear();

    const Eigen::Vector2d centre = Tag::params().template segment<2>(2);
    for (int v = 8; v < kTestHeight - 8; v += 12) {
      for (int u = 8; u < kTestWidth - 8; u += 12) {
        const Eigen::Vector2d p0(u, v);
        if ((p0 - centre).norm() > 100.0) continue;
        Eigen::Vector3d bearing;
        if (!camera.unproject(p0, bearing)) continue;
        const double d = 1.0 / scene.distanceAlong(T_world_host, bearing);
        PhotometricObservation<kN> obs;
        obs.host = makeHostPatch<kN>(
            host_pyramid_->level(level), host_pyramid_->gradients(level),
            Eigen::Vector2d(pixelToLevel(p0.x(), level), pixelToLevel(p0.y(), level)));
        obs.target_image = &target_pyramid_->level(level);
        obs.host_exposure = host_photometry.exposure;
        obs.target_exposure = target_photometry.exposure;
        obs.level = level;
        truth_.inverse_distances.push_back(d);
        observations_.push_back(obs);
        if (!allValid(truth_)) {  // keep points that are valid at the truth
          truth_.inverse_distances.pop_back();
          observations_.pop_back();
        }
      }
    }
    costs_.clear();
    for (const auto& obs : observations_) {
      costs_.emplace_back(Tag::photometric(DifferentiationMode::kAnalytic, obs));
    }
  }

  std::array<const double*, 6> blocksOf(const State<K>& s, size_t i) const {
    return {s.host_pose.data(),   s.target_pose.data(),   &s.inverse_distances[i],
            s.host_affine.data(), s.target_affine.data(), s.intrinsics.data()};
  }

  bool allValid(const State<K>& s) const {
    for (size_t i = 0; i < observations_.size(); ++i) {
      if (Tag::status(observations_[i], blocksOf(s, i).data()) != PhotometricStatus::kValid) {
        return false;
      }
    }
    return true;
  }

  // ½ Σ ‖r‖² without the robust loss; +∞ if any residual is invalid.
  double cost(const State<K>& s) const {
    double total = 0.0;
    std::array<double, kN> r;
    for (size_t i = 0; i < costs_.size(); ++i) {
      if (!costs_[i]->Evaluate(blocksOf(s, i).data(), r.data(), nullptr)) {
        return std::numeric_limits<double>::infinity();
      }
      for (double x : r) total += 0.5 * x * x;
    }
    return total;
  }

  std::unique_ptr<ImagePyramid> host_pyramid_, target_pyramid_;
  State<K> truth_;
  std::vector<PhotometricObservation<kN>> observations_;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;
};

using Models = ::testing::Types<Pinhole, Ucm, Eucm, Ds, Kb4, Fov>;
TYPED_TEST_SUITE(PhotometricSceneTest, Models);

std::array<double, 7> plus(const std::array<double, 7>& x, const Eigen::Matrix<double, 6, 1>& d) {
  std::array<double, 7> out;
  SE3Manifold().Plus(x.data(), d.data(), out.data());
  return out;
}

TYPED_TEST(PhotometricSceneTest, CostIsMinimalAtGroundTruth) {
  using S = State<TypeParam::kNumParams>;
  for (int level = 0; level <= 1; ++level) {
    this->setUp(level);
    ASSERT_GE(this->observations_.size(), 40u) << "level " << level;
    const double at_truth = this->cost(this->truth_);
    // Perturbations move the target pixels by about one level-0 pixel or change the
    // brightness by a few units: far above the rendering/interpolation error that keeps the
    // cost at the truth from being exactly zero.
    std::vector<std::pair<const char*, std::function<void(S&, double)>>> perturbations = {
        {"target translation",
         [](S& s, double sign) {
           Eigen::Matrix<double, 6, 1> d;
           d << 0.03 * sign, -0.02 * sign, 0.02 * sign, 0, 0, 0;
           s.target_pose = plus(s.target_pose, d);
         }},
        {"target rotation",
         [](S& s, double sign) {
           Eigen::Matrix<double, 6, 1> d;
           d << 0, 0, 0, 0.01 * sign, -0.008 * sign, 0.01 * sign;
           s.target_pose = plus(s.target_pose, d);
         }},
        {"host rotation",
         [](S& s, double sign) {
           Eigen::Matrix<double, 6, 1> d;
           d << 0, 0, 0, -0.008 * sign, 0.01 * sign, 0.01 * sign;
           s.host_pose = plus(s.host_pose, d);
         }},
        {"inverse distance",
         [](S& s, double sign) {
           for (double& d : s.inverse_distances) d *= 1.0 + 0.3 * sign;
         }},
        {"host affine a", [](S& s, double sign) { s.host_affine[0] += 0.05 * sign; }},
        {"host affine b", [](S& s, double sign) { s.host_affine[1] += 4.0 * sign; }},
        {"target affine a", [](S& s, double sign) { s.target_affine[0] += 0.05 * sign; }},
        {"target affine b", [](S& s, double sign) { s.target_affine[1] += 4.0 * sign; }},
    };
    for (int k = 0; k < TypeParam::kNumParams; ++k) {
      // fx, fy ±2 %, cx, cy ±2 px, model parameters ±0.02 (absolute, as KB4's k_i are small).
      perturbations.push_back(
          {TypeParam::template Camera<double>::kParamNames[k], [k](S& s, double sign) {
             const double step = k < 2 ? 0.02 * s.intrinsics[k] : k < 4 ? 2.0 : 0.02;
             s.intrinsics[k] += sign * step;
           }});
    }
    for (const auto& [name, perturb] : perturbations) {
      for (double sign : {-1.0, 1.0}) {
        S perturbed = this->truth_;
        perturb(perturbed, sign);
        EXPECT_GT(this->cost(perturbed), at_truth) << "level " << level << ": " << name << " "
                                                   << sign << " (cost at truth " << at_truth << ")";
      }
    }
  }
}

// Target pose, target affine and the inverse distances from a perturbed start; host pose,
// host affine, intrinsics and one inverse distance (the monocular scale gauge) are fixed.
TYPED_TEST(PhotometricSceneTest, CeresRecoversGroundTruthFromPerturbedStart) {
  for (int level = 0; level <= 1; ++level) {
    this->setUp(level);
    State<TypeParam::kNumParams> s = this->truth_;
    Eigen::Matrix<double, 6, 1> pose_error;
    pose_error << 0.03, -0.02, 0.02, 0.01, -0.008, 0.01;  // ~1–2 px at the image centre
    s.target_pose = plus(s.target_pose, pose_error);
    s.target_affine[0] += 0.1;
    s.target_affine[1] += 5.0;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (size_t i = 1; i < s.inverse_distances.size(); ++i)
      s.inverse_distances[i] *= 1.0 + jitter(rng);

    SE3Manifold se3;
    ceres::Problem::Options problem_options;
    problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    for (size_t i = 0; i < this->observations_.size(); ++i) {
      // As a caller must: drop residuals that are invalid at the start (pinhole points near
      // the border leave the image under the start perturbation).
      if (TypeParam::status(this->observations_[i], this->blocksOf(s, i).data()) !=
          PhotometricStatus::kValid) {
        continue;
      }
      problem.AddResidualBlock(
          TypeParam::photometric(DifferentiationMode::kAnalytic, this->observations_[i]),
          makePhotometricLoss(kN), s.host_pose.data(), s.target_pose.data(),
          &s.inverse_distances[i], s.host_affine.data(), s.target_affine.data(),
          s.intrinsics.data());
    }
    problem.SetManifold(s.host_pose.data(), &se3);
    problem.SetManifold(s.target_pose.data(), &se3);
    problem.SetParameterBlockConstant(s.host_pose.data());
    problem.SetParameterBlockConstant(s.host_affine.data());
    problem.SetParameterBlockConstant(s.intrinsics.data());
    problem.SetParameterBlockConstant(&s.inverse_distances[0]);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::DENSE_SCHUR;
    options.max_num_iterations = 50;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    ASSERT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();

    const SE3d error = SE3d::fromParameters(s.target_pose.data()).inverse() *
                       SE3d::fromParameters(this->truth_.target_pose.data());
    const Eigen::Matrix<double, 6, 1> e = error.log();
    std::vector<double> d_errors;
    for (size_t i = 0; i < s.inverse_distances.size(); ++i) {
      d_errors.push_back(
          std::abs(s.inverse_distances[i] / this->truth_.inverse_distances[i] - 1.0));
    }
    std::sort(d_errors.begin(), d_errors.end());
    const double median_d_error = d_errors[d_errors.size() / 2];
    SCOPED_TRACE(testing::Message()
                 << "level " << level << " " << summary.BriefReport() << "\nrotation error "
                 << e.tail<3>().norm() << " translation error " << e.head<3>().norm() << " affine "
                 << s.target_affine[0] - this->truth_.target_affine[0] << " "
                 << s.target_affine[1] - this->truth_.target_affine[1] << " median d error "
                 << median_d_error);
    EXPECT_LT(e.tail<3>().norm(), kMaxRotationError);
    EXPECT_LT(e.head<3>().norm(), kMaxTranslationError);
    EXPECT_NEAR(s.target_affine[0], this->truth_.target_affine[0], kMaxAffineAError);
    EXPECT_NEAR(s.target_affine[1], this->truth_.target_affine[1], kMaxAffineBError);
    EXPECT_LT(median_d_error, kMaxMedianInverseDistanceError);
  }
}

}  // namespace
}  // namespace omnidso::test
