// The native marginalisation of window points (window_point_marginalization.hpp).
#include <cmath>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/backend/window_point_marginalization.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

// x ⊟ x̄ over frame space (window_problem.hpp); zero on constant blocks.
Eigen::VectorXd frameSpaceDelta(const WindowProblem& current, const WindowProblem& first_estimate) {
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(current.frameSpaceSize());
  for (size_t f = 0; f < current.frames.size(); ++f) {
    const WindowFrame& x = current.frames[f];
    const WindowFrame& x_bar = first_estimate.frames[f];
    const int offset = kFrameTangentSize * static_cast<int>(f);
    if (!x.pose_constant) current.pose_manifold->Minus(x.pose, x_bar.pose, delta.data() + offset);
    if (!x.affine_constant)
      for (int i = 0; i < 2; ++i) delta[offset + 6 + i] = x.affine[i] - x_bar.affine[i];
  }
  if (!current.intrinsics_constant)
    for (int i = 0; i < current.num_intrinsics; ++i)
      delta[current.intrinsicsOffset() + i] = current.intrinsics[i] - first_estimate.intrinsics[i];
  return delta;
}

}  // namespace

PointSchurComplement marginalizePoints(const WindowProblem& current,
                                       const WindowProblem& first_estimate,
                                       WindowPhotometricTerms::ImageGradientAt gradient_at) {
  if (current.frames.size() != first_estimate.frames.size() ||
      current.points.size() != first_estimate.points.size() ||
      current.residuals.size() != first_estimate.residuals.size())
    throw Error(
        "marginalizePoints: the two problems must have the same frames, points and residuals");
  const int num_points = static_cast<int>(current.points.size());
  WindowNormalEquations equations;
  equations.reset(current.frameSpaceSize(), num_points);
  current.photometric->linearizeAt(current, first_estimate, &equations, gradient_at);

  // g = Σ J̃ᵀr̃ − H (x ⊟ x̄): the frames' part and each point's (δ_p = 0: a point's x̄ is x).
  const Eigen::VectorXd delta = frameSpaceDelta(current, first_estimate);
  const Eigen::VectorXd g_f = equations.frameGradient() - equations.frameHessian() * delta;
  const Eigen::VectorXd g_p = equations.pointGradient() - equations.pointCoupling() * delta;

  // K: the variable blocks some residual touches, and their frame-space columns.
  PointSchurComplement out;
  std::vector<char> touched(current.frames.size(), 0);
  for (const WindowResidual& residual : current.residuals) {
    touched[static_cast<size_t>(current.points[residual.point].host)] = 1;
    touched[static_cast<size_t>(residual.target)] = 1;
  }
  std::vector<int> columns;
  auto addBlock = [&](double* values, int offset, int size) {
    out.blocks.push_back(values);
    for (int i = 0; i < size; ++i) columns.push_back(offset + i);
  };
  for (size_t f = 0; f < current.frames.size(); ++f) {
    if (!touched[f]) continue;
    const WindowFrame& frame = current.frames[f];
    const int offset = kFrameTangentSize * static_cast<int>(f);
    if (!frame.pose_constant) addBlock(frame.pose, offset, 6);
    if (!frame.affine_constant) addBlock(frame.affine, offset + 6, 2);
  }
  if (!current.intrinsics_constant && !current.residuals.empty())
    addBlock(current.intrinsics, current.intrinsicsOffset(), current.num_intrinsics);

  // The points' Schur terms as one rank update, in point order: ŵ_p = w_p / √h_p.
  const int k = static_cast<int>(columns.size());
  Eigen::MatrixXd scaled_coupling = Eigen::MatrixXd::Zero(num_points, k);
  Eigen::VectorXd scaled_gradient = Eigen::VectorXd::Zero(num_points);
  for (int p = 0; p < num_points; ++p) {
    const double h = equations.pointHessian()[p];
    if (current.points[p].constant || !(h > 0.0)) continue;
    const double inverse_sqrt_h = 1.0 / std::sqrt(h);
    for (int c = 0; c < k; ++c)
      scaled_coupling(p, c) = equations.pointCoupling()(p, columns[c]) * inverse_sqrt_h;
    scaled_gradient[p] = g_p[p] * inverse_sqrt_h;
  }
  out.information.resize(k, k);
  out.gradient.resize(k);
  for (int a = 0; a < k; ++a) {
    out.gradient[a] = g_f[columns[a]];
    for (int b = 0; b < k; ++b)
      out.information(a, b) = equations.frameHessian()(columns[a], columns[b]);
  }
  out.information.noalias() -= scaled_coupling.transpose() * scaled_coupling;
  out.information = 0.5 * (out.information + out.information.transpose()).eval();
  out.gradient.noalias() -= scaled_coupling.transpose() * scaled_gradient;
  return out;
}

}  // namespace omnidso
