// Evaluation metrics: statistics, timestamp association (gaps, rates, conflicts, against a
// brute-force TUM-style greedy matcher), hand-computed RPE, ATE of noisy and exact copies,
// and the real EuRoC ground truth aligned to a Sim(3) copy of itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <random>
#include <tuple>

#include "test_data.hpp"

namespace omnidso {
namespace {

Trajectory stampsOnly(const std::vector<double>& stamps) {
  Trajectory out;
  for (const double t : stamps) out.push_back({t, SE3d()});
  return out;
}

SE3d pose(double yaw_deg, const Eigen::Vector3d& t) {
  return SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * EIGEN_PI / 180.0, Eigen::Vector3d::UnitZ())), t);
}

// All pairs within max_dt sorted by (|Δt|, gt, est), accepted greedily: TUM associate.py.
Association bruteForceAssociate(const Trajectory& gt, const Trajectory& est, double max_dt) {
  std::vector<std::tuple<double, size_t, size_t>> candidates;
  for (size_t j = 0; j < gt.size(); ++j) {
    for (size_t i = 0; i < est.size(); ++i) {
      const double dt = std::abs(gt[j].timestamp - est[i].timestamp);
      if (dt <= max_dt) candidates.emplace_back(dt, j, i);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> gt_used(gt.size()), est_used(est.size());
  Association out;
  for (const auto& [dt, j, i] : candidates) {
    if (gt_used[j] || est_used[i]) continue;
    gt_used[j] = est_used[i] = true;
    out.emplace_back(j, i);
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Metrics, StatisticsMatchHandComputedValues) {
  const ErrorStatistics even = computeStatistics({4.0, 1.0, 3.0, 2.0});
  EXPECT_DOUBLE_EQ(even.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(even.mean, 2.5);
  EXPECT_DOUBLE_EQ(even.median, 2.5);  // mean of the two middle values, as numpy
  EXPECT_DOUBLE_EQ(even.std, std::sqrt(1.25));  // population std, as numpy.std
  EXPECT_EQ(even.min, 1.0);
  EXPECT_EQ(even.max, 4.0);
  EXPECT_EQ(computeStatistics({3.0, 1.0, 2.0}).median, 2.0);
  EXPECT_THROW(computeStatistics({}), Error);
}

TEST(Metrics, AssociationHandlesGapsAndDifferentRates) {
  // 100 Hz ground truth over 0..3 s with a gap (0.5, 1.2); 20 Hz estimate offset by 3 ms,
  // with every 7th pose missing.
  std::vector<double> gt_stamps, est_stamps;
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.01 * k;
    if (t < 0.5 || t > 1.2) gt_stamps.push_back(t);
  }
  for (int k = 0; k < 60; ++k) {
    if (k % 7 != 3) est_stamps.push_back(0.05 * k + 0.003);
  }
  const Trajectory gt = stampsOnly(gt_stamps), est = stampsOnly(est_stamps);
  const Association matches = associate(gt, est, 0.02);
  // Estimate poses are 0.05 s apart (> 2 max_dt), so no two compete: each matches its
  // nearest ground truth if that is within 0.02 s — 3 ms away except inside the gap.
  size_t expected = 0;
  for (const auto& [j, i] : matches) {
    EXPECT_LE(std::abs(gt[j].timestamp - est[i].timestamp), 0.02);
  }
  for (const double t : est_stamps) {
    if (t < 0.5 + 0.02 || t > 1.2 - 0.02) ++expected;
  }
  EXPECT_EQ(matches.size(), expected);
  for (size_t k = 1; k < matches.size(); ++k) {
    EXPECT_LT(matches[k - 1].first, matches[k].first);    // order preserved
    EXPECT_LT(matches[k - 1].second, matches[k].second);  // no crossing here
  }
  // A faster estimate than ground truth: every ground-truth pose is used exactly once.
  const Association reversed = associate(est, gt, 0.02);
  for (const auto& [j, i] : reversed) {
    EXPECT_LE(std::abs(est[j].timestamp - gt[i].timestamp), 0.003 + 1e-12);
  }
  EXPECT_EQ(reversed.size(), expected);
}

TEST(Metrics, AssociationGivesEachGroundTruthPoseToItsNearestEstimate) {
  // Both estimates are within 0.02 s of gt 1.0; the nearer (1.005) wins it, and 0.99 is
  // left unmatched because gt 0.0 is too far.
  const Association matches = associate(stampsOnly({0.0, 1.0}), stampsOnly({0.99, 1.005}), 0.02);
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0], std::make_pair(size_t{1}, size_t{1}));
}

TEST(Metrics, AssociationEqualsBruteForceGreedyMatching) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> step(0.001, 0.03);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> a, b;
    double ta = 0.0, tb = 0.0;
    for (int k = 0; k < 200; ++k) a.push_back(ta += step(rng));
    for (int k = 0; k < 150; ++k) b.push_back(tb += 1.3 * step(rng));
    const Trajectory gt = stampsOnly(a), est = stampsOnly(b);
    EXPECT_EQ(associate(gt, est, 0.02), bruteForceAssociate(gt, est, 0.02)) << trial;
  }
}

TEST(Metrics, PathLengthCountsOnlyPosesInsideTheTimeSpan) {
  // Poses along x at 0, 1, 3, 6 m (t = 0..3 s): 1 + 2 + 3 = 6 m in all, 2 + 3 = 5 m from t = 1.
  Trajectory t;
  const double xs[] = {0, 1, 3, 6};
  for (int i = 0; i < 4; ++i)
    t.push_back({double(i), SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(xs[i], 0, 0))});
  EXPECT_DOUBLE_EQ(pathLength(t, 0.0, 3.0), 6.0);
  EXPECT_DOUBLE_EQ(pathLength(t, 0.5, 3.0), 5.0);
  EXPECT_DOUBLE_EQ(pathLength(t, 1.0, 2.0), 2.0);
  EXPECT_DOUBLE_EQ(pathLength(t, 1.5, 1.9), 0.0);
}

TEST(Metrics, NoOverlapThrows) {
  const Trajectory gt = stampsOnly({0.0, 0.1, 0.2, 0.3});
  const Trajectory est = stampsOnly({10.0, 10.1, 10.2, 10.3});
  EXPECT_THROW(evaluate(gt, est, EvaluationOptions{}), Error);
}

TEST(Metrics, RelativePoseErrorIsMeasuredInTheFirstPoseFrame) {
  // The estimate never turns; the ground truth turns to yaw 90° while moving to pose 1.
  // Pair (0,1): the estimate also overshoots 0.1 m sideways: E = (Rz(−90°), Rz(90°)ᵀ(0, 0.1, 0))
  //   → 0.1 m, 90°.
  // Pair (1,2): both move 1 m along world y — for the ground truth (facing +y) that is along
  //   its own x, for the estimate along its own y. Relative motions (1,0,0) vs (0,1,0):
  //   error √2 m and no rotation error.
  const Trajectory gt = {{0, pose(0, {0, 0, 0})}, {1, pose(90, {1, 0, 0})}, {2, pose(90, {1, 1, 0})}};
  const Trajectory est = {{0, pose(0, {0, 0, 0})}, {1, pose(0, {1, 0.1, 0})}, {2, pose(0, {1, 1.1, 0})}};
  const RelativeErrors rpe =
      relativePoseErrors(gt, est, associateByIndex(gt, est), Sim3d(), RpeOptions{});
  ASSERT_EQ(rpe.pairs.size(), 2u);
  // Composition of a few exact transforms: rounding is ~1e-16 per operation; angles come
  // from atan2 of rounded quaternions (~1e-14 deg).
  EXPECT_NEAR(rpe.translation_m[0], 0.1, 1e-12);
  EXPECT_NEAR(rpe.rotation_deg[0], 90.0, 1e-9);
  EXPECT_NEAR(rpe.translation_m[1], std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(rpe.rotation_deg[1], 0.0, 1e-9);
}

TEST(Metrics, RelativePosePairsFollowEvoForFramesAndMetres) {
  // 10 poses 0.4 m apart along x.
  Trajectory line;
  for (int k = 0; k < 10; ++k) line.push_back({0.1 * k, pose(0, {0.4 * k, 0, 0})});
  const Association all = associateByIndex(line, line);
  RpeOptions frames;
  frames.delta = 4;
  const auto by_frames = relativePoseErrors(line, line, all, Sim3d(), frames).pairs;
  const std::vector<std::pair<size_t, size_t>> expected_frames = {{0, 4}, {4, 8}};
  EXPECT_EQ(by_frames, expected_frames);
  // Path reaches 1 m at index 3 (1.2 m), then 3 more steps each time: 3, 6, 9.
  RpeOptions metres;
  metres.delta = 1.0;
  metres.unit = DeltaUnit::kMeters;
  const auto by_metres = relativePoseErrors(line, line, all, Sim3d(), metres).pairs;
  const std::vector<std::pair<size_t, size_t>> expected_metres = {{3, 6}, {6, 9}};
  EXPECT_EQ(by_metres, expected_metres);
  frames.delta = 2.5;
  EXPECT_THROW(relativePoseErrors(line, line, all, Sim3d(), frames), Error);
}

TEST(Metrics, ScaledEstimateHasZeroErrorsOnlyAfterSim3Alignment) {
  // A trajectory at half scale, rotated and shifted: Sim(3) alignment explains it fully.
  Trajectory gt, est;
  const Sim3d world_change(0.5, Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized())),
                           Eigen::Vector3d(3, -1, 2));
  for (int k = 0; k < 40; ++k) {
    const SE3d g = pose(9.0 * k, {std::cos(0.2 * k), std::sin(0.3 * k), 0.05 * k});
    gt.push_back({0.05 * k, g});
    est.push_back({0.05 * k + 0.001, world_change * g});
  }
  EvaluationOptions options;
  options.alignment = AlignmentType::kSim3;
  const EvaluationResult sim3 = evaluate(gt, est, options);
  EXPECT_EQ(sim3.association.size(), 40u);
  // Exact data: errors are rounding-level relative to the ~1 m extent.
  EXPECT_LT(sim3.ate.max, 1e-12);
  EXPECT_LT(sim3.rpe_translation_m->max, 1e-12);
  EXPECT_LT(sim3.rpe_rotation_deg->max, 1e-9);
  EXPECT_NEAR(sim3.alignment.scale(), 2.0, 1e-12);
  // Rigid alignment cannot undo the scale: each relative translation is half as long,
  // so the RPE translation is half the ground-truth step length (rotations are unaffected).
  options.alignment = AlignmentType::kSE3;
  const EvaluationResult se3 = evaluate(gt, est, options);
  EXPECT_GT(se3.ate.rmse, 0.1);
  const RelativeErrors rpe = relativePoseErrors(gt, est, se3.association, se3.alignment, options.rpe);
  for (size_t k = 0; k < rpe.pairs.size(); ++k) {
    const auto [i, j] = rpe.pairs[k];
    const double step = (gt[j].pose.translation() - gt[i].pose.translation()).norm();
    EXPECT_NEAR(rpe.translation_m[k], 0.5 * step, 1e-12);
    EXPECT_LT(rpe.rotation_deg[k], 1e-9);
  }
}

TEST(Metrics, AteOfNoisyCopyIsTheNoiseLevel) {
  // Positions perturbed by isotropic N(0, σ²): after alignment the errors are the noise
  // minus its (tiny, 7-parameter) fitted part, so RMSE ≈ √3 σ. With N = 3000 the RMSE's
  // relative standard deviation is 1/√(2·3N) ≈ 0.8%; 4% is 5 standard deviations.
  const double sigma = 0.02;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  Trajectory gt, est;
  for (int k = 0; k < 3000; ++k) {
    const double t = 0.01 * k;
    const SE3d g = pose(t * 20.0, {3 * std::cos(0.5 * t), 2 * std::sin(0.7 * t), std::sin(t)});
    gt.push_back({t, g});
    est.push_back({t, SE3d(g.rotation(), g.translation() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)))});
  }
  const EvaluationResult r = evaluate(gt, est, EvaluationOptions{});
  EXPECT_NEAR(r.ate.rmse / (std::sqrt(3.0) * sigma), 1.0, 0.04);
  // Length: Σ of consecutive distances of the ground truth (all poses associated).
  double length = 0.0;
  for (size_t k = 1; k < gt.size(); ++k) length += (gt[k].pose.translation() - gt[k - 1].pose.translation()).norm();
  EXPECT_NEAR(r.gt_length_m, length, 1e-9);
}

TEST(Metrics, RealEurocTrajectoryAlignsToItsSim3Copy) {
  const auto dir = test::sharedDataDir("trajectories");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("trajectories");
  const Trajectory gt = readTrajectoryTum((*dir / "euroc_v1_01_easy_imu_groundtruth.txt").string());
  const Sim3d known(0.37, Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Eigen::Vector3d(0.2, -1, 0.4).normalized())),
                    Eigen::Vector3d(-5, 12, 0.3));
  // Every other pose, 4 ms late: different rate and a time offset below max_dt.
  Trajectory est;
  for (size_t k = 0; k < gt.size(); k += 2) est.push_back({gt[k].timestamp + 0.004, known * gt[k].pose});
  const EvaluationResult r = evaluate(gt, est, EvaluationOptions{});
  EXPECT_EQ(r.association.size(), est.size());
  // ~58 m of flight within a few metres of the origin: rounding-level errors (1e-15 relative).
  EXPECT_LT(r.ate.rmse, 1e-9);
  EXPECT_NEAR(r.alignment.scale(), 1.0 / known.scale(), 1e-9);
  EXPECT_GT(r.gt_length_m, 50.0);  // V1_01_easy: about 58 m at 20 Hz
}

}  // namespace
}  // namespace omnidso
