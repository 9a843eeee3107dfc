#pragma once
// Internal to the fitting problems (model_fitting.cc, calibration/board_adjustment.cc): the
// pixel residual π(p) − target of one point through a camera model, in doubles or Jets.
// Outside the model's domain — or where its arithmetic degenerates — the residual is a
// constant penalty with zero derivative: finite, so Ceres never sees NaN, and larger than any
// fit error, so steps that push points out of the domain raise the cost and are rejected.

#include <ceres/jet.h>

#include <Eigen/Core>
#include <cmath>

namespace omnidso::detail {

inline bool allFinite(double x) { return std::isfinite(x); }
template <typename T, int N>
bool allFinite(const ceres::Jet<T, N>& x) {
  return std::isfinite(x.a) && x.v.allFinite();
}

template <typename ModelT, typename T>
void penalisedProjectionResidual(const ModelT& model, const Eigen::Matrix<T, 3, 1>& p,
                                 const Eigen::Vector2d& target, double penalty_px,
                                 T* residual) {
  Eigen::Matrix<T, 2, 1> uv;
  if (model.project(p, uv) && allFinite(uv.x()) && allFinite(uv.y())) {
    residual[0] = uv.x() - T(target.x());
    residual[1] = uv.y() - T(target.y());
  } else {
    residual[0] = T(penalty_px);
    residual[1] = T(penalty_px);
  }
}

}  // namespace omnidso::detail
