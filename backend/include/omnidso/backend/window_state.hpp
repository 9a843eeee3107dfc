#pragma once
// The state x of the native window solver: the variable parameter blocks of a WindowProblem
// that some residual uses — Ceres's reduced program — in ambient coordinates. The solver
// moves the blocks in place (x ⊞ δ, each block by its manifold: SE3Manifold's Plus for
// poses, x + δ otherwise) and restores them when a candidate is rejected, so the result lands
// where Ceres writes its own. Also the norms of Ceres's tolerances, in ambient coordinates:
//   ‖x‖, ‖x − x'‖ (parameter tolerance) and ‖x − (x ⊞ −g)‖_∞ (gradient tolerance).

#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_problem.hpp>
#include <vector>

namespace omnidso {

class WindowState {
 public:
  explicit WindowState(const WindowProblem& problem);

  // The coordinates the linear system solves for.
  const WindowVariables& variables() const { return variables_; }

  void save(std::vector<double>* x) const;
  void restore(const std::vector<double>& x);
  // x ← x ⊞ δ; δ in frame space and per point (window_problem.hpp).
  void plus(const Eigen::VectorXd& frame_step, const Eigen::VectorXd& point_step);

  double norm() const;
  double distanceTo(const std::vector<double>& x) const;
  // ‖x − (x ⊞ −g)‖_∞ with g = J̃ᵀr̃ from `equations`.
  double gradientMaxNorm(const WindowNormalEquations& equations) const;

 private:
  static constexpr int kMaxBlockSize = 16;  // poses 7, intrinsics up to 8
  struct Block {
    double* values = nullptr;
    int ambient_size = 0;
    int tangent_size = 0;
    int offset = 0;          // frame-space offset, or the point index
    bool is_point = false;
    const ceres::Manifold* manifold = nullptr;
  };
  std::vector<Block> blocks_;
  int num_ambient_ = 0;
  WindowVariables variables_;
};

}  // namespace omnidso
