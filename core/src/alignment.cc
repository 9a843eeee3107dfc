// Umeyama alignment (formulas in alignment.hpp).
#include <Eigen/SVD>
#include <cmath>
#include <omnidso/core/alignment.hpp>
#include <omnidso/core/error.hpp>
#include <string>

namespace omnidso {
namespace {

// A second singular value of the cross-covariance below this fraction of the first means
// the points are collinear (or coincide) up to rounding: the rotation about that line is
// then undetermined. Real trajectories, even nearly straight ones, are far above it.
constexpr double kDegenerateRatio = 1e-10;

void checkSizes(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt, Eigen::Index minimum,
                const char* what) {
  if (est.cols() != gt.cols()) {
    throw Error(std::string(what) + ": " + std::to_string(est.cols()) + " estimated and " +
                std::to_string(gt.cols()) + " ground-truth points do not correspond");
  }
  if (est.cols() < minimum) {
    throw Error(std::string(what) + ": needs at least " + std::to_string(minimum) +
                " corresponding points, got " + std::to_string(est.cols()));
  }
}

struct UmeyamaResult {
  double scale;
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};

UmeyamaResult umeyama(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt, bool with_scale,
                      const char* what) {
  checkSizes(est, gt, 3, what);
  const double n = static_cast<double>(est.cols());
  const Eigen::Vector3d mean_est = est.rowwise().mean();
  const Eigen::Vector3d mean_gt = gt.rowwise().mean();
  const Eigen::Matrix3Xd centred_est = est.colwise() - mean_est;
  const Eigen::Matrix3Xd centred_gt = gt.colwise() - mean_gt;
  const Eigen::Matrix3d covariance = centred_gt * centred_est.transpose() / n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();
  if (!(d(1) > kDegenerateRatio * d(0))) {
    throw Error(std::string(what) +
                ": points are collinear or coincide, the rotation is not determined");
  }
  Eigen::Vector3d signs(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) signs(2) = -1.0;
  UmeyamaResult result;
  result.rotation = svd.matrixU() * signs.asDiagonal() * svd.matrixV().transpose();
  const double variance_est = centred_est.squaredNorm() / n;
  result.scale = with_scale ? d.dot(signs) / variance_est : 1.0;
  result.translation = mean_gt - result.scale * result.rotation * mean_est;
  return result;
}

}  // namespace

Sim3d alignSim3(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt) {
  const UmeyamaResult r = umeyama(est, gt, true, "Sim(3) alignment");
  return Sim3d(r.scale, r.rotation, r.translation);
}

SE3d alignSE3(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt) {
  const UmeyamaResult r = umeyama(est, gt, false, "SE(3) alignment");
  return SE3d(r.rotation, r.translation);
}

SE3d alignPositionYaw(const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt) {
  const char* what = "position-yaw alignment";
  checkSizes(est, gt, 2, what);
  const Eigen::Vector3d mean_est = est.rowwise().mean();
  const Eigen::Vector3d mean_gt = gt.rowwise().mean();
  const Eigen::Matrix3Xd e = est.colwise() - mean_est;
  const Eigen::Matrix3Xd g = gt.colwise() - mean_gt;
  const double sin_part = (e.row(0).cwiseProduct(g.row(1)) - e.row(1).cwiseProduct(g.row(0))).sum();
  const double cos_part = (e.row(0).cwiseProduct(g.row(0)) + e.row(1).cwiseProduct(g.row(1))).sum();
  const double spread = std::sqrt(e.topRows<2>().squaredNorm() * g.topRows<2>().squaredNorm());
  if (!(std::hypot(sin_part, cos_part) > kDegenerateRatio * spread) || spread == 0.0) {
    throw Error(std::string(what) + ": points coincide in x-y, the yaw is not determined");
  }
  const double yaw = std::atan2(sin_part, cos_part);
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return SE3d(rotation, mean_gt - rotation * mean_est);
}

}  // namespace omnidso
