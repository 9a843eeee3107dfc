// ATE, RPE and their statistics (definitions in metrics.hpp).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <omnidso/core/alignment.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/metrics.hpp>

namespace omnidso {
namespace {

constexpr double kRadToDeg = 180.0 / EIGEN_PI;

// The matched positions as two 3×N matrices (ground truth, estimate).
std::pair<Eigen::Matrix3Xd, Eigen::Matrix3Xd> matchedPositions(const Trajectory& gt,
                                                               const Trajectory& est,
                                                               const Association& association) {
  Eigen::Matrix3Xd g(3, static_cast<Eigen::Index>(association.size()));
  Eigen::Matrix3Xd e(3, static_cast<Eigen::Index>(association.size()));
  for (size_t k = 0; k < association.size(); ++k) {
    g.col(static_cast<Eigen::Index>(k)) = gt.at(association[k].first).pose.translation();
    e.col(static_cast<Eigen::Index>(k)) = est.at(association[k].second).pose.translation();
  }
  return {g, e};
}

// Rotation angle of a unit quaternion in [0, π]: 2 atan2(|v|, |w|), accurate at all angles
// (unlike acos((tr R − 1)/2) near 0).
double rotationAngle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

// evo's consecutive pairs by accumulated path length (metrics.hpp).
std::vector<size_t> indicesByPath(const std::vector<SE3d>& poses, double delta) {
  std::vector<size_t> ids;
  double path = 0.0;
  for (size_t i = 1; i < poses.size(); ++i) {
    path += (poses[i].translation() - poses[i - 1].translation()).norm();
    if (path >= delta) {
      ids.push_back(i);
      path = 0.0;
    }
  }
  return ids;
}

}  // namespace

AlignmentType parseAlignmentType(const std::string& name) {
  if (name == "sim3") return AlignmentType::kSim3;
  if (name == "se3") return AlignmentType::kSE3;
  if (name == "posyaw") return AlignmentType::kPositionYaw;
  if (name == "none") return AlignmentType::kNone;
  throw Error("unknown alignment '" + name + "' (expected sim3, se3, posyaw or none)");
}

DeltaUnit parseDeltaUnit(const std::string& name) {
  if (name == "f") return DeltaUnit::kFrames;
  if (name == "m") return DeltaUnit::kMeters;
  throw Error("unknown delta unit '" + name + "' (expected f or m)");
}

Sim3d alignTrajectories(const Trajectory& gt, const Trajectory& est,
                        const Association& association, AlignmentType type) {
  const auto [g, e] = matchedPositions(gt, est, association);
  switch (type) {
    case AlignmentType::kSim3:
      return alignSim3(e, g);
    case AlignmentType::kSE3:
      return Sim3d(alignSE3(e, g));
    case AlignmentType::kPositionYaw:
      return Sim3d(alignPositionYaw(e, g));
    case AlignmentType::kNone:
      break;
  }
  return Sim3d::identity();
}

ErrorStatistics computeStatistics(const std::vector<double>& errors) {
  if (errors.empty()) throw Error("error statistics of an empty list");
  ErrorStatistics stats;
  const double n = static_cast<double>(errors.size());
  stats.count = errors.size();
  stats.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / n;
  double squares = 0.0, deviations = 0.0;
  for (const double e : errors) {
    squares += e * e;
    deviations += (e - stats.mean) * (e - stats.mean);
  }
  stats.rmse = std::sqrt(squares / n);
  stats.std = std::sqrt(deviations / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t half = sorted.size() / 2;
  stats.median = sorted.size() % 2 == 1 ? sorted[half] : 0.5 * (sorted[half - 1] + sorted[half]);
  stats.min = sorted.front();
  stats.max = sorted.back();
  return stats;
}

std::vector<double> absolutePositionErrors(const Trajectory& gt, const Trajectory& est,
                                           const Association& association,
                                           const Sim3d& alignment) {
  std::vector<double> errors;
  errors.reserve(association.size());
  for (const auto& [g, e] : association) {
    errors.push_back((alignment * est.at(e).pose.translation() - gt.at(g).pose.translation()).norm());
  }
  return errors;
}

double groundTruthLength(const Trajectory& gt, const Association& association) {
  double length = 0.0;
  for (size_t k = 1; k < association.size(); ++k) {
    length += (gt.at(association[k].first).pose.translation() -
               gt.at(association[k - 1].first).pose.translation())
                  .norm();
  }
  return length;
}

double pathLength(const Trajectory& trajectory, double t0, double t1) {
  double length = 0.0;
  const StampedPose* last = nullptr;
  for (const StampedPose& p : trajectory) {
    if (p.timestamp < t0 || p.timestamp > t1) continue;
    if (last) length += (p.pose.translation() - last->pose.translation()).norm();
    last = &p;
  }
  return length;
}

RelativeErrors relativePoseErrors(const Trajectory& gt, const Trajectory& est,
                                  const Association& association, const Sim3d& alignment,
                                  const RpeOptions& options) {
  std::vector<SE3d> gt_poses, est_poses;
  for (const auto& [g, e] : association) {
    gt_poses.push_back(gt.at(g).pose);
    est_poses.push_back(alignment * est.at(e).pose);
  }
  std::vector<size_t> ids;
  if (options.unit == DeltaUnit::kFrames) {
    if (!(options.delta >= 1.0) || options.delta != std::floor(options.delta)) {
      throw Error("RPE: a delta in frames must be a positive integer");
    }
    const auto step = static_cast<size_t>(options.delta);
    for (size_t i = 0; i < est_poses.size(); i += step) ids.push_back(i);
  } else {
    if (!(options.delta > 0.0)) throw Error("RPE: a delta in metres must be positive");
    ids = indicesByPath(options.pairs_from_reference ? gt_poses : est_poses, options.delta);
  }
  RelativeErrors out;
  for (size_t k = 1; k < ids.size(); ++k) {
    const size_t i = ids[k - 1], j = ids[k];
    const SE3d gt_relative = gt_poses[i].inverse() * gt_poses[j];
    const SE3d est_relative = est_poses[i].inverse() * est_poses[j];
    const SE3d error = gt_relative.inverse() * est_relative;
    out.pairs.emplace_back(i, j);
    out.translation_m.push_back(error.translation().norm());
    out.rotation_deg.push_back(rotationAngle(error.rotation()) * kRadToDeg);
  }
  return out;
}

EvaluationResult evaluate(const Trajectory& gt, const Trajectory& est,
                          const EvaluationOptions& options) {
  EvaluationResult result;
  result.association = options.associate_by_index ? associateByIndex(gt, est)
                                                  : associate(gt, est, options.max_dt);
  if (result.association.empty()) {
    throw Error("no estimated pose has a ground-truth pose within max_dt = " +
                std::to_string(options.max_dt) + " s: the trajectories do not overlap");
  }
  result.alignment = alignTrajectories(gt, est, result.association, options.alignment);
  result.position_errors = absolutePositionErrors(gt, est, result.association, result.alignment);
  result.ate = computeStatistics(result.position_errors);
  result.gt_length_m = groundTruthLength(gt, result.association);
  const RelativeErrors rpe =
      relativePoseErrors(gt, est, result.association, result.alignment, options.rpe);
  if (!rpe.pairs.empty()) {
    result.rpe_translation_m = computeStatistics(rpe.translation_m);
    result.rpe_rotation_deg = computeStatistics(rpe.rotation_deg);
  }
  return result;
}

}  // namespace omnidso
