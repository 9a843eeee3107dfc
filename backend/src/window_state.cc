// WindowState (window_state.hpp): the reduced program's blocks — variable, and used by a
// residual — in a fixed order (points by id, then keyframes oldest first, then the
// intrinsics), and the in-place moves and norms of the native solver.
#include <algorithm>
#include <cmath>
#include <omnidso/backend/window_state.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {

WindowState::WindowState(const WindowProblem& problem) {
  // Which frame-space coordinates some residual uses (Ceres leaves unused blocks out of the
  // reduced program).
  std::vector<char> used(problem.frameSpaceSize(), 0);
  auto markUsed = [&](int offset, int size) { std::fill_n(used.begin() + offset, size, 1); };
  for (const WindowPointBlock& point : problem.points) {
    if (point.num_residuals == 0) continue;
    markUsed(kFrameTangentSize * point.host, kFrameTangentSize);
    markUsed(problem.intrinsicsOffset(), problem.num_intrinsics);
    for (int k = point.first_residual; k < point.first_residual + point.num_residuals; ++k)
      markUsed(kFrameTangentSize * problem.residuals[k].target, kFrameTangentSize);
  }
  for (const WindowPrior& prior : problem.priors)
    for (const WindowPriorBlock& b : prior.blocks) markUsed(b.tangent_offset, b.tangent_size);

  for (size_t p = 0; p < problem.points.size(); ++p) {
    const WindowPointBlock& point = problem.points[p];
    variables_.point_variable.push_back(!point.constant && point.num_residuals > 0);
    if (variables_.point_variable.back())
      blocks_.push_back({point.inverse_distance, 1, 1, static_cast<int>(p), true, nullptr});
  }
  auto addFrameBlock = [&](double* values, int ambient, int tangent, int offset, bool constant,
                           const ceres::Manifold* manifold) {
    if (constant || !used[offset]) return;
    blocks_.push_back({values, ambient, tangent, offset, false, manifold});
    for (int i = 0; i < tangent; ++i) variables_.frame_columns.push_back(offset + i);
  };
  for (size_t f = 0; f < problem.frames.size(); ++f) {
    const WindowFrame& frame = problem.frames[f];
    const int offset = kFrameTangentSize * static_cast<int>(f);
    addFrameBlock(frame.pose, 7, 6, offset, frame.pose_constant, problem.pose_manifold);
    addFrameBlock(frame.affine, 2, 2, offset + 6, frame.affine_constant, nullptr);
  }
  addFrameBlock(problem.intrinsics, problem.num_intrinsics, problem.num_intrinsics,
                problem.intrinsicsOffset(), problem.intrinsics_constant, nullptr);
  for (const Block& b : blocks_) {
    if (b.ambient_size > kMaxBlockSize || b.tangent_size > kMaxBlockSize)
      throw Error("WindowState: a parameter block of more than 16 numbers");
    num_ambient_ += b.ambient_size;
  }
}

void WindowState::save(std::vector<double>* x) const {
  x->resize(num_ambient_);
  auto out = x->begin();
  for (const Block& b : blocks_) out = std::copy_n(b.values, b.ambient_size, out);
}

void WindowState::restore(const std::vector<double>& x) {
  auto in = x.begin();
  for (const Block& b : blocks_) {
    std::copy_n(in, b.ambient_size, b.values);
    in += b.ambient_size;
  }
}

void WindowState::plus(const Eigen::VectorXd& frame_step, const Eigen::VectorXd& point_step) {
  double moved[kMaxBlockSize];
  for (const Block& b : blocks_) {
    if (b.is_point) {
      b.values[0] = b.values[0] + point_step[b.offset];
    } else if (b.manifold) {
      b.manifold->Plus(b.values, frame_step.data() + b.offset, moved);
      std::copy_n(moved, b.ambient_size, b.values);
    } else {
      for (int i = 0; i < b.ambient_size; ++i) b.values[i] = b.values[i] + frame_step[b.offset + i];
    }
  }
}

double WindowState::norm() const {
  double sum = 0.0;
  for (const Block& b : blocks_)
    for (int i = 0; i < b.ambient_size; ++i) sum += b.values[i] * b.values[i];
  return std::sqrt(sum);
}

double WindowState::distanceTo(const std::vector<double>& x) const {
  double sum = 0.0;
  auto in = x.begin();
  for (const Block& b : blocks_)
    for (int i = 0; i < b.ambient_size; ++i, ++in) sum += (*in - b.values[i]) * (*in - b.values[i]);
  return std::sqrt(sum);
}

double WindowState::gradientMaxNorm(const WindowNormalEquations& equations) const {
  double max_norm = 0.0;
  double negative_gradient[kMaxBlockSize], moved[kMaxBlockSize];
  for (const Block& b : blocks_) {
    for (int i = 0; i < b.tangent_size; ++i)
      negative_gradient[i] = -(b.is_point ? equations.pointGradient()[b.offset]
                                          : equations.frameGradient()[b.offset + i]);
    if (b.manifold) {
      b.manifold->Plus(b.values, negative_gradient, moved);
    } else {
      for (int i = 0; i < b.ambient_size; ++i) moved[i] = b.values[i] + negative_gradient[i];
    }
    for (int i = 0; i < b.ambient_size; ++i)
      max_norm = std::max(max_norm, std::abs(b.values[i] - moved[i]));
  }
  return max_norm;
}

}  // namespace omnidso
