// WindowNormalEquations (window_normal_equations.hpp): the Schur complement of the points,
// the dense Cholesky solve of the reduced camera system, the back-substitution, and the
// model cost change of the Levenberg–Marquardt step.
#include <algorithm>
#include <cmath>
#include <omnidso/backend/window_normal_equations.hpp>

namespace omnidso {

void WindowNormalEquations::reset(int frame_space_size, int num_points) {
  H_ff_.setZero(frame_space_size, frame_space_size);
  g_f_.setZero(frame_space_size);
  h_p_.setZero(num_points);
  g_p_.setZero(num_points);
  W_.setZero(num_points, frame_space_size);
}

void WindowNormalEquations::swap(WindowNormalEquations& other) noexcept {
  H_ff_.swap(other.H_ff_);
  g_f_.swap(other.g_f_);
  h_p_.swap(other.h_p_);
  g_p_.swap(other.g_p_);
  W_.swap(other.W_);
  lhs_.swap(other.lhs_);
  rhs_.swap(other.rhs_);
  scaled_coupling_.swap(other.scaled_coupling_);
  scaled_gradient_.swap(other.scaled_gradient_);
}

double WindowNormalEquations::dampedPointHessian(int p,
                                                 const LevenbergMarquardtDamping& damping) const {
  return h_p_[p] + damping.squaredDiagonal(h_p_[p]);
}

void WindowNormalEquations::reducedCameraSystem(const WindowVariables& variables,
                                                const LevenbergMarquardtDamping& damping,
                                                Eigen::MatrixXd* lhs,
                                                Eigen::VectorXd* rhs) const {
  const std::vector<int>& columns = variables.frame_columns;
  const int n = static_cast<int>(columns.size());
  lhs->resize(n, n);
  rhs->resize(n);
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) (*lhs)(i, j) = H_ff_(columns[i], columns[j]);
    (*lhs)(j, j) += damping.squaredDiagonal(H_ff_(columns[j], columns[j]));
    (*rhs)[j] = g_f_[columns[j]];
  }
  // Σ_p w_pᵀ w_p / (h_p + D_p²) as one rank update with ŵ_p = w_p / √(h_p + D_p²).
  const int num_points = numPoints();
  RowMatrix& scaled = scaled_coupling_;
  Eigen::VectorXd& scaled_gradient = scaled_gradient_;
  scaled.resize(num_points, n);
  scaled_gradient.resize(num_points);
  for (int p = 0; p < num_points; ++p) {
    if (!variables.point_variable[p]) {
      scaled.row(p).setZero();
      scaled_gradient[p] = 0.0;
      continue;
    }
    const double scale = 1.0 / std::sqrt(dampedPointHessian(p, damping));
    for (int j = 0; j < n; ++j) scaled(p, j) = W_(p, columns[j]) * scale;
    scaled_gradient[p] = g_p_[p] * scale;
  }
  lhs->selfadjointView<Eigen::Lower>().rankUpdate(scaled.transpose(), -1.0);
  rhs->noalias() -= scaled.transpose() * scaled_gradient;
}

bool WindowNormalEquations::solveStep(const WindowVariables& variables,
                                      const LevenbergMarquardtDamping& damping,
                                      Eigen::VectorXd* frame_step, Eigen::VectorXd* point_step) {
  reducedCameraSystem(variables, damping, &lhs_, &rhs_);
  cholesky_.compute(lhs_);
  if (cholesky_.info() != Eigen::Success) return false;
  const Eigen::VectorXd y = cholesky_.solve(rhs_);
  Eigen::VectorXd y_f = Eigen::VectorXd::Zero(frameSpaceSize());
  for (size_t j = 0; j < variables.frame_columns.size(); ++j) y_f[variables.frame_columns[j]] = y[j];
  const Eigen::VectorXd coupled = W_ * y_f;
  *frame_step = -y_f;
  point_step->setZero(numPoints());
  for (int p = 0; p < numPoints(); ++p) {
    if (!variables.point_variable[p]) continue;
    const double inverse = 1.0 / dampedPointHessian(p, damping);
    (*point_step)[p] = -(inverse * (g_p_[p] - coupled[p]));
  }
  return frame_step->allFinite() && point_step->allFinite();
}

double WindowNormalEquations::modelCostChange(const Eigen::VectorXd& frame_step,
                                              const Eigen::VectorXd& point_step) const {
  const double gradient_term = frame_step.dot(g_f_) + point_step.dot(g_p_);
  const Eigen::VectorXd coupled = W_ * frame_step;
  double curvature = frame_step.dot(H_ff_ * frame_step);
  for (int p = 0; p < numPoints(); ++p)
    curvature += point_step[p] * (2.0 * coupled[p] + h_p_[p] * point_step[p]);
  return -gradient_term - 0.5 * curvature;
}

}  // namespace omnidso
