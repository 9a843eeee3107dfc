#include "omnidso/cameras/calibration/initial_estimate.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

constexpr int kFocalCandidates = 48;
constexpr double kMinFocalDiagonals = 0.05;
constexpr double kMaxFocalDiagonals = 2.0;

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::infinity();
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

// Poses of every view and the median reprojection error through `camera`; views whose pose
// cannot be found get the identity and count as an infinite error.
double posesAndMedianError(const Camera& camera, const BoardDetections& detections,
                           const BoardSpec& board, std::vector<SE3d>& poses) {
  std::vector<Eigen::Vector3d> board_points;
  for (int k = 0; k < board.numCorners(); ++k) board_points.push_back(board.corner(k));
  poses.assign(detections.views.size(), SE3d());
  std::vector<double> errors;
  for (size_t v = 0; v < detections.views.size(); ++v) {
    std::vector<Eigen::Vector3d> bearings;
    for (const Eigen::Vector2d& uv : detections.views[v].corners) {
      Eigen::Vector3d b;
      if (!camera.unproject(uv, b)) break;
      bearings.push_back(b);
    }
    const bool posed = bearings.size() == board_points.size() &&
                       boardPoseFromBearings(board_points, bearings, poses[v]);
    for (int k = 0; k < board.numCorners(); ++k) {
      Eigen::Vector2d uv;
      const bool ok = posed && std::visit([&](const auto& m) {
                        return m.project(poses[v] * board_points[k], uv);
                      }, camera.model());
      errors.push_back(ok ? (uv - detections.views[v].corners[k]).norm()
                          : std::numeric_limits<double>::infinity());
    }
  }
  return median(errors);
}

}  // namespace

bool boardPoseFromBearings(const std::vector<Eigen::Vector3d>& board_points,
                           const std::vector<Eigen::Vector3d>& bearings, SE3d& T_camera_board) {
  const int n = static_cast<int>(board_points.size());
  if (n < 4 || static_cast<int>(bearings.size()) != n) return false;
  // Centre and scale the board coordinates: x' = (x − c)/s.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& X : board_points) centre += X.head<2>();
  centre /= n;
  double scale = 0.0;
  for (const Eigen::Vector3d& X : board_points) scale += (X.head<2>() - centre).norm();
  scale /= n;
  if (!(scale > 0.0)) return false;
  // b × (H x') = 0: rows [b]× ⊗ x'ᵀ acting on the row-major 9-vector of H.
  Eigen::MatrixXd A(3 * n, 9);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d x((board_points[i].x() - centre.x()) / scale,
                            (board_points[i].y() - centre.y()) / scale, 1.0);
    const Eigen::Vector3d& b = bearings[i];
    Eigen::Matrix3d bx;
    bx << 0, -b.z(), b.y(), b.z(), 0, -b.x(), -b.y(), b.x(), 0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) A.block<1, 3>(3 * i + r, 3 * c) = bx(r, c) * x.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd s = svd.singularValues();
  if (!(s[7] > 1e-9 * s[0])) return false;  // more than one null direction: degenerate
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d H;
  H << h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8];
  // Undo the normalisation: H_board = H · N, N = [1/s 0 −cx/s; 0 1/s −cy/s; 0 0 1].
  Eigen::Matrix3d N;
  N << 1 / scale, 0, -centre.x() / scale, 0, 1 / scale, -centre.y() / scale, 0, 0, 1;
  H = H * N;
  double lambda = 2.0 / (H.col(0).norm() + H.col(1).norm());
  // The board lies along the bearings, not behind the camera: b · (H x) > 0.
  double sign_votes = 0.0;
  for (int i = 0; i < n; ++i)
    sign_votes += bearings[i].dot(H * Eigen::Vector3d(board_points[i].x(), board_points[i].y(), 1));
  if (sign_votes < 0) lambda = -lambda;
  H *= lambda;
  Eigen::Matrix3d R;
  R << H.col(0), H.col(1), H.col(0).cross(H.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> rot(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  R = rot.matrixU() * rot.matrixV().transpose();
  if (R.determinant() < 0) return false;
  T_camera_board = SE3d(R, Eigen::Vector3d(H.col(2)));
  return true;
}

InitialCalibration initialEquidistantCalibration(const BoardDetections& detections,
                                                 const BoardSpec& board) {
  const double cx = 0.5 * (detections.width - 1);
  const double cy = 0.5 * (detections.height - 1);
  const double diagonal = std::hypot(detections.width, detections.height);
  Eigen::VectorXd start(8);
  start << 1, 1, cx, cy, 0, 0, 0, 0;
  InitialCalibration best{Camera::create("kb4", start, detections.width, detections.height), {},
                          std::numeric_limits<double>::infinity()};
  for (int i = 0; i < kFocalCandidates; ++i) {
    const double f = diagonal * kMinFocalDiagonals *
                     std::pow(kMaxFocalDiagonals / kMinFocalDiagonals,
                              static_cast<double>(i) / (kFocalCandidates - 1));
    Eigen::VectorXd params(8);
    params << f, f, cx, cy, 0, 0, 0, 0;
    const Camera camera = Camera::create("kb4", params, detections.width, detections.height);
    std::vector<SE3d> poses;
    const double error = posesAndMedianError(camera, detections, board, poses);
    if (error < best.median_error_px) best = {camera, std::move(poses), error};
  }
  if (!std::isfinite(best.median_error_px)) {
    throw Error("calibration: no focal length gives a board pose for any view");
  }
  return best;
}

}  // namespace omnidso
