// The native marginalisation of window points (backend/window_point_marginalization.hpp)
// against the same Schur complement formed from Ceres's own linearisation of the points'
// residual blocks (ceres::Problem::Evaluate: J̃ at the first estimate, r̃ at the current
// values), on a rendered window whose frames and intrinsics have first estimates apart from
// their current values.
#include <ceres/crs_matrix.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <omnidso/backend/window_point_marginalization.hpp>

#include "window_test_scenes.hpp"

namespace omnidso {
namespace {

using test::perturbedWindow;
using test::WindowScene;

constexpr int kNumKeyframes = 4;
constexpr int kHost = 1;  // the keyframe whose points are marginalised

const Camera& testCamera() { return test::sweepCamera(); }

const WindowScene& testScene() { return test::sweepScene(kNumKeyframes); }

// The points of `window` hosted by frame `host` (and their residuals), no priors; and the
// same problem with every frame and the intrinsics at a first estimate x̄ a little apart from
// x (values kept in `storage`), as a marginalisation meets them after a few solves.
struct PointProblems {
  WindowProblem current, first_estimate;
  std::vector<Eigen::VectorXd> storage;
};

PointProblems pointProblems(const WindowProblem& window, int host) {
  PointProblems out;
  WindowProblem& current = out.current;
  current = window;
  current.priors.clear();
  current.points.clear();
  current.residuals.clear();
  ++current.id;  // another problem for the terms' caches
  for (const WindowPointBlock& point : window.points) {
    if (point.host != host) continue;
    WindowPointBlock copy = point;
    copy.first_residual = static_cast<int>(current.residuals.size());
    for (int k = point.first_residual; k < point.first_residual + point.num_residuals; ++k)
      current.residuals.push_back({static_cast<int>(current.points.size()), window.residuals[k].target});
    current.points.push_back(copy);
  }
  out.storage.reserve(2 * current.frames.size() + 1);
  auto moved = [&](const double* x, int size, double step) {
    Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(x, size);
    for (int i = 0; i < size; ++i) v[i] += step * ((i % 3) - 1.0);
    out.storage.push_back(v);
    return out.storage.back().data();
  };
  // Constant blocks (the gauge, fixed intrinsics) are known: their x̄ is x.
  out.first_estimate = current;
  for (WindowFrame& f : out.first_estimate.frames) {
    if (!f.pose_constant) {
      Eigen::Matrix<double, 6, 1> xi;
      xi << 0.004, -0.003, 0.002, 0.003, 0.002, -0.004;  // ≈ 5 mm, 0.3°
      Eigen::VectorXd pose(7);
      (SE3d::fromParameters(f.pose) * SE3d::exp(xi)).toParameters(pose.data());
      out.storage.push_back(pose);
      f.pose = out.storage.back().data();
    }
    if (!f.affine_constant) f.affine = moved(f.affine, 2, 0.01);
  }
  if (!current.intrinsics_constant)
    out.first_estimate.intrinsics = moved(current.intrinsics, current.num_intrinsics, 0.3);
  return out;
}

// Ceres's Jacobian of the residual blocks `ids` at the problem's values, over `columns`
// (parameter blocks side by side); the residuals too. Loss and manifolds applied.
void evaluateWithCeres(ceres::Problem& problem, const std::vector<ceres::ResidualBlockId>& ids,
                       const std::vector<double*>& columns, Eigen::MatrixXd* J,
                       Eigen::VectorXd* r) {
  ceres::Problem::EvaluateOptions options;
  options.residual_blocks = ids;
  options.parameter_blocks = columns;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  ASSERT_TRUE(problem.Evaluate(options, nullptr, &residuals, nullptr, &crs));
  J->setZero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) (*J)(row, crs.cols[k]) = crs.values[k];
  *r = Eigen::Map<const Eigen::VectorXd>(residuals.data(), static_cast<int>(residuals.size()));
}

class WindowPointMarginalization : public ::testing::TestWithParam<bool> {};

// H* and g* of marginalizePoints against the dense Schur complement of Ceres's linearisation:
//   r₀ = r̃(x) − J̃(x̄)(x ⊟ x̄),  H = J̃ᵀJ̃,  g = J̃ᵀr₀,  H* = H_KK − H_KM H_MM⁻¹ H_MK, likewise g*.
// Tolerances: H* is positive semi-definite, so |H*_ij| ≤ √(H_ii H_jj) (the same bound for
// its terms), and |g*_i| ≤ √H_ii ‖r₀‖; both sides sum ≈ 10³ products, a rounding error of
// ≈ 10⁻¹³ of those bounds, and the Jacobians differ by a few ε (Ceres: J·P⁺ for the poses,
// the native terms J_ε·Ad). 10⁻⁹ of the bound leaves a wide margin; a Jacobian at the wrong
// point (x instead of x̄, 5 mm and 0.3° apart) or a residual without its δ term is an error
// of order 10⁻³ or more of it.
TEST_P(WindowPointMarginalization, FormsTheSchurComplementOfCeresLinearization) {
  WindowOptions options = test::recoveryOptions(kNumKeyframes, GetParam());
  auto window = perturbedWindow(testCamera(), testScene(), options, kNumKeyframes);
  window->removeOutliers();
  const std::optional<WindowProblem> native = window->nativeProblem();
  ASSERT_TRUE(native);
  PointProblems problems = pointProblems(*native, kHost);
  ASSERT_GT(problems.current.points.size(), 20u);
  // Ceres evaluates a residual block's whole Jacobian at x̄, the image gradient included; the
  // odometry's linearisation takes that at x (DSO; WindowFirstEstimate tests it).
  const PointSchurComplement schur =
      marginalizePoints(problems.current, problems.first_estimate,
                        WindowPhotometricTerms::ImageGradientAt::kFirstEstimate);

  // Ceres: the same residual blocks, columns [points | the frames' variable blocks | c].
  ceres::Problem& problem = window->mutableProblem();
  std::vector<ceres::ResidualBlockId> ids;
  std::vector<double*> columns;
  for (const auto& [pid, point] : window->points()) {
    if (point->host_id != window->keyframeIds()[kHost]) continue;
    for (const auto& [target, id] : point->residuals) ids.push_back(id);
    columns.push_back(&point->inverse_distance);
  }
  const int m = static_cast<int>(columns.size());
  ASSERT_EQ(m, static_cast<int>(problems.current.points.size()));
  std::vector<double*> frame_blocks;
  for (const WindowFrame& f : problems.current.frames) {
    if (!f.pose_constant) frame_blocks.push_back(f.pose);
    if (!f.affine_constant) frame_blocks.push_back(f.affine);
  }
  if (!problems.current.intrinsics_constant) frame_blocks.push_back(problems.current.intrinsics);
  columns.insert(columns.end(), frame_blocks.begin(), frame_blocks.end());

  Eigen::MatrixXd J_at_x, J;
  Eigen::VectorXd r, r_at_x_bar;
  evaluateWithCeres(problem, ids, columns, &J_at_x, &r);
  // x ⊟ x̄ per frame block, then the blocks set to x̄ for the Jacobian, and restored.
  std::vector<Eigen::VectorXd> saved;
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(J_at_x.cols());
  std::vector<int> offsets;  // of each frame block's columns
  int column = m;
  for (double* block : frame_blocks) {
    const int ambient = problem.ParameterBlockSize(block);
    const int tangent = problem.ParameterBlockTangentSize(block);
    const double* x_bar = nullptr;
    for (size_t f = 0; f < problems.current.frames.size(); ++f) {
      if (block == problems.current.frames[f].pose) x_bar = problems.first_estimate.frames[f].pose;
      if (block == problems.current.frames[f].affine) x_bar = problems.first_estimate.frames[f].affine;
    }
    if (block == problems.current.intrinsics) x_bar = problems.first_estimate.intrinsics;
    ASSERT_NE(x_bar, nullptr);
    const ceres::Manifold* manifold = problem.GetManifold(block);
    if (manifold) {
      manifold->Minus(block, x_bar, delta.data() + column);
    } else {
      for (int i = 0; i < ambient; ++i) delta[column + i] = block[i] - x_bar[i];
    }
    saved.emplace_back(Eigen::Map<const Eigen::VectorXd>(block, ambient));
    std::copy(x_bar, x_bar + ambient, block);
    offsets.push_back(column);
    column += tangent;
  }
  evaluateWithCeres(problem, ids, columns, &J, &r_at_x_bar);
  for (size_t b = 0; b < frame_blocks.size(); ++b)
    std::copy(saved[b].data(), saved[b].data() + saved[b].size(), frame_blocks[b]);
  ASSERT_GT((J - J_at_x).norm(), 1e-3 * J.norm()) << "x̄ must be apart from x";

  const Eigen::VectorXd r0 = r - J * delta;
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::VectorXd g = J.transpose() * r0;
  const int n = static_cast<int>(J.cols()) - m;
  Eigen::MatrixXd H_star = H.bottomRightCorner(n, n);
  Eigen::VectorXd g_star = g.tail(n);
  for (int p = 0; p < m; ++p) {
    if (!(H(p, p) > 0.0)) continue;
    H_star -= H.block(m, p, n, 1) * H.block(p, m, 1, n) / H(p, p);
    g_star -= H.block(m, p, n, 1) * g[p] / H(p, p);
  }

  // The native K, block by block, in the oracle's frame-space columns.
  std::vector<int> oracle_columns;
  for (double* block : schur.blocks) {
    const auto it = std::find(frame_blocks.begin(), frame_blocks.end(), block);
    ASSERT_NE(it, frame_blocks.end());
    const int b = static_cast<int>(it - frame_blocks.begin());
    for (int i = 0; i < problem.ParameterBlockTangentSize(block); ++i)
      oracle_columns.push_back(offsets[b] - m + i);
  }
  const int k = static_cast<int>(oracle_columns.size());
  ASSERT_EQ(schur.information.rows(), k);
  ASSERT_EQ(schur.gradient.size(), k);
  // Every frame block the residuals touch is in K: the others' columns are zero.
  for (int c = 0; c < n; ++c) {
    if (std::find(oracle_columns.begin(), oracle_columns.end(), c) == oracle_columns.end()) {
      EXPECT_EQ(H(m + c, m + c), 0.0) << "frame-space column " << c << " left out of K";
    }
  }
  const double r0_norm = r0.norm();
  for (int a = 0; a < k; ++a) {
    const int ia = oracle_columns[a];
    const double sa = std::sqrt(H(m + ia, m + ia));
    EXPECT_NEAR(schur.gradient[a], g_star[ia], 1e-9 * sa * r0_norm) << "g* " << a;
    for (int b = 0; b < k; ++b) {
      const int ib = oracle_columns[b];
      EXPECT_NEAR(schur.information(a, b), H_star(ia, ib),
                  1e-9 * sa * std::sqrt(H(m + ib, m + ib)))
          << "H* (" << a << ", " << b << ")";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Intrinsics, WindowPointMarginalization, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "Optimised" : "Constant"; });

}  // namespace
}  // namespace omnidso
