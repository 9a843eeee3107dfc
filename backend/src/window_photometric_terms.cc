// The photometric residuals of the native window solver (window_photometric_terms.hpp): the
// kernel of residuals/photometric_kernel.hpp per (point, target) residual, the Jacobian in
// relative-pose form, JᵀJ summed per host–target pair and per point, and the pairs mapped
// to the frames' blocks. Instantiated for every camera model with a residual kernel.
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/cameras/double_sphere.hpp>
#include <omnidso/cameras/extended_unified.hpp>
#include <omnidso/cameras/fov.hpp>
#include <omnidso/cameras/kannala_brandt.hpp>
#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/cameras/unified.hpp>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/residuals/photometric_kernel.hpp>
#include <limits>
#include <utility>

namespace omnidso {
namespace {

constexpr int kN = kWindowPatternSize;
// Columns of one residual's pair Jacobian: ε = [ρ φ] of T_th, α, γ (header), intrinsics.
// β = √w s = −s γ within a pair, so its column is not stored: the pair-to-frames map applies
// the factor (pairToFrames, and the points' rows in accumulate).
constexpr int kEpsilon = 0, kAlpha = 6, kGamma = 7, kPairIntrinsics = 8;

template <template <typename> class Camera>
class PhotometricTermsOf final : public WindowPhotometricTerms {
  using CameraD = Camera<double>;
  static constexpr int K = CameraD::kNumParams;
  static constexpr int kColumns = kPairIntrinsics + K;  // pair columns and intrinsics
  static constexpr int kGramSize = kColumns + 1;         // … and r̃
  using Gram = Eigen::Matrix<double, kGramSize, kGramSize>;
  using Rows = Eigen::Matrix<double, kN, kGramSize, Eigen::RowMajor>;  // [J | r̃] of a residual
  struct PairGram {
    Gram lower;  // ΣAᵀA over the pair's residuals, lower triangle only
    bool used = false;
  };
  using Adjoint = Eigen::Matrix<double, 6, 6>;
  using PairToFrames = Eigen::Matrix<double, kPairIntrinsics, 2 * kFrameTangentSize>;
  using PatchResiduals = Eigen::Matrix<double, kN, 1>;
  // Where the r̃ of the Gram matrices' last column comes from: each residual's own
  // evaluation (kOwn; kKeep also keeps r, r̃ and ∇I_j for the next pass), or the one the
  // previous pass kept: kKept with the kept ∇I_j and robust weight (DSO's first-estimate
  // Jacobians), kKeptWithOwnGradient with this pass's (the whole Jacobian at its values).
  enum class ResidualSource { kOwn, kKeep, kKept, kKeptWithOwnGradient };

 public:
  double evaluate(const WindowProblem& problem, WindowNormalEquations* equations,
                  std::vector<double>* energies) override {
    return evaluatePass(problem, equations, energies, ResidualSource::kOwn);
  }

  void linearizeAt(const WindowProblem& current, const WindowProblem& first_estimate,
                   WindowNormalEquations* equations, ImageGradientAt gradient_at) override {
    evaluatePass(current, nullptr, nullptr, ResidualSource::kKeep);
    evaluatePass(first_estimate, equations, nullptr, gradient_at == ImageGradientAt::kCurrentEstimate
                                                         ? ResidualSource::kKept
                                                         : ResidualSource::kKeptWithOwnGradient);
  }

  double evaluateAt(const WindowProblem& current, const WindowProblem& first_estimate,
                    WindowNormalEquations* equations, std::vector<double>* energies) override {
    const double cost = evaluatePass(current, nullptr, energies, ResidualSource::kKeep);
    if (equations) evaluatePass(first_estimate, equations, nullptr, ResidualSource::kKept);
    return cost;
  }

 private:
  double evaluatePass(const WindowProblem& problem, WindowNormalEquations* equations,
                      std::vector<double>* energies, ResidualSource source) {
    const int num_frames = num_frames_ = static_cast<int>(problem.frames.size());
    typename CameraD::VecN intrinsics = Eigen::Map<const typename CameraD::VecN>(problem.intrinsics);
    scaleIntrinsicsToLevel(intrinsics, 0);  // as the cost function does (level 0)
    const CameraD camera(intrinsics);
    const bool want_intrinsics = equations && !problem.intrinsics_constant;
    refreshBearings(problem, camera, intrinsics);

    std::vector<ImageSampler> samplers;
    samplers.reserve(num_frames);
    for (const WindowFrame& f : problem.frames)
      samplers.emplace_back(*f.image, problem.interpolation, f.content, problem.gradient);
    pairs_.resize(static_cast<size_t>(num_frames) * num_frames);
    adjoints_.resize(pairs_.size());
    for (int h = 0; h < num_frames; ++h)
      for (int t = 0; t < num_frames; ++t) {
        if (h == t) continue;
        const WindowFrame& host = problem.frames[h];
        const WindowFrame& target = problem.frames[t];
        const int pair = h * num_frames + t;
        pairs_[pair] = makePhotometricPair(host.pose, target.pose, host.affine, target.affine,
                                           host.exposure, target.exposure);
        if (equations) adjoints_[pair] = adjointOf(pairs_[pair]);
      }
    if (equations) {  // a pair with residuals gets its Gram matrix from its task below
      pair_grams_.resize(pairs_.size());
      for (PairGram& g : pair_grams_) g.used = false;
    }

    // The residuals are evaluated pair by pair on the compute threads: each pair's Gram
    // matrix is summed by one task in residual order, and what each residual adds to the
    // cost and to its point (h_p, g_p, w_p) is kept and summed below in residual order —
    // the same operations in the same order as one pass over the residuals, so the result
    // does not depend on the thread count (core/task_pool.hpp).
    const int num_residuals = static_cast<int>(problem.residuals.size());
    groupResidualsByPair(problem);
    terms_.resize(num_residuals);
    const bool keep = source == ResidualSource::kKeep;
    const bool kept_gradient = source == ResidualSource::kKept;
    const bool kept = kept_gradient || source == ResidualSource::kKeptWithOwnGradient;
    if (keep) kept_.resize(num_residuals);
    const bool with_equations = equations != nullptr;
    // OutOfBoundsPenalty's constant residual √(E/N) per pixel.
    const PatchResiduals penalty = PatchResiduals::Constant(std::sqrt(problem.out_of_bounds_energy / kN));
    const RobustCorrection invalid_correction(problem.photometric_loss, penalty.squaredNorm());
    runTasks(problem.pool, static_cast<int>(used_pairs_.size()), [&](int task) {
      const int pair = used_pairs_[task];
      Eigen::Matrix<double, kN, 1> r;
      PatchDerivatives<kN, K> patch;
      // The pair's Gram matrix is summed on the task's stack and stored once: neighbouring
      // pairs' matrices share cache lines, which two threads should not write per residual.
      PairGram gram;
      gram.lower.setZero();
      for (int i = pair_begin_[pair]; i < pair_begin_[pair + 1]; ++i) {
        const int k = residuals_by_pair_[i];
        const int p = problem.residuals[k].point;
        const WindowPointBlock& point = problem.points[p];
        ResidualTerms& terms = terms_[i];
        if (kept_gradient && !kept_[i].valid) {  // r is the constant penalty: no gradient
          terms.valid = false;
          continue;
        }
        const PhotometricStatus status = evaluatePhotometricPatch(
            camera, samplers[problem.residuals[k].target], *point.patch, bearings_[p],
            pairs_[pair], *point.inverse_distance, r.data(), with_equations ? &patch : nullptr,
            want_intrinsics, keep ? &kept_[i].image_gradients : nullptr,
            kept_gradient ? &kept_[i].image_gradients : nullptr);
        terms.valid = status == PhotometricStatus::kValid;
        if (keep) kept_[i].valid = terms.valid;
        if (!terms.valid) {  // a zero Jacobian: nothing to accumulate
          if (keep) {
            kept_[i].residuals = penalty;
            invalid_correction.correctResiduals(kept_[i].residuals);
          }
          continue;
        }
        if (kept_gradient) r = kept_[i].raw_residuals;  // robust-weighted at the kept r
        terms.energy = r.squaredNorm();
        const RobustCorrection correction(problem.photometric_loss, r.squaredNorm());
        terms.cost = correction.cost();
        if (keep) {
          kept_[i].raw_residuals = r;
          kept_[i].residuals = r;
          correction.correctResiduals(kept_[i].residuals);
        }
        if (with_equations)
          accumulate(*point.patch, patch, pair, *point.inverse_distance, r, correction,
                     kept ? &kept_[i].residuals : nullptr, want_intrinsics, &gram, &terms);
      }
      if (with_equations) pair_grams_[pair] = gram;
    });

    const double invalid_cost = invalid_correction.cost();
    if (energies) energies->resize(num_residuals);
    double cost = 0.0;
    for (int k = 0; k < num_residuals; ++k) {
      const ResidualTerms& terms = terms_[position_by_pair_[k]];
      if (!terms.valid) {
        cost += invalid_cost;
        if (energies) (*energies)[k] = std::numeric_limits<double>::infinity();
        continue;
      }
      if (energies) (*energies)[k] = terms.energy;
      cost += terms.cost;
      if (equations) {
        const WindowResidual& residual = problem.residuals[k];
        addToPoint(terms, problem.points[residual.point].host * num_frames + residual.target,
                   residual.point, equations);
      }
    }
    if (equations) addPairsToFrames(problem, equations);
    return cost;
  }

  // b_o (and ∂b_o/∂c when the intrinsics are variable) per point, kept while the
  // intrinsics are the same.
  void refreshBearings(const WindowProblem& problem, const CameraD& camera,
                       const typename CameraD::VecN& intrinsics) {
    const bool with_jacobian = !problem.intrinsics_constant;
    if (bearings_problem_ == problem.id && bearings_.size() == problem.points.size() &&
        bearings_intrinsics_ == intrinsics && (bearings_have_jacobian_ || !with_jacobian))
      return;
    bearings_.resize(problem.points.size());
    for (size_t p = 0; p < problem.points.size(); ++p)
      unprojectHostPattern(camera, *problem.points[p].patch, with_jacobian, &bearings_[p]);
    bearings_problem_ = problem.id;
    bearings_intrinsics_ = intrinsics;
    bearings_have_jacobian_ = with_jacobian;
  }

  // What one valid residual adds to its point's h_p, g_p and row of W: J̃_d and v = J̃_dᵀ J̃
  // (pair columns), kept by the parallel pass and summed in residual order by addToPoint.
  struct ResidualTerms {
    bool valid = false;
    double energy = 0.0, cost = 0.0;
    double point_hessian = 0.0, point_gradient = 0.0;
    Eigen::Matrix<double, 1, kColumns> v;
  };

  // Residual indices grouped by host–target pair, in residual order within a pair (a
  // counting sort), and the pairs that have any.
  void groupResidualsByPair(const WindowProblem& problem) {
    const int num_pairs = num_frames_ * num_frames_;
    pair_begin_.assign(num_pairs + 1, 0);
    for (const WindowResidual& residual : problem.residuals)
      ++pair_begin_[problem.points[residual.point].host * num_frames_ + residual.target + 1];
    used_pairs_.clear();
    for (int pair = 0; pair < num_pairs; ++pair) {
      if (pair_begin_[pair + 1] > 0) used_pairs_.push_back(pair);
      pair_begin_[pair + 1] += pair_begin_[pair];
    }
    residuals_by_pair_.resize(problem.residuals.size());
    position_by_pair_.resize(problem.residuals.size());
    std::vector<int> next(pair_begin_.begin(), pair_begin_.end() - 1);
    for (int k = 0; k < static_cast<int>(problem.residuals.size()); ++k) {
      const WindowResidual& residual = problem.residuals[k];
      const int position = next[problem.points[residual.point].host * num_frames_ + residual.target]++;
      residuals_by_pair_[position] = k;
      position_by_pair_[k] = position;
    }
  }

  // One valid residual: its rows [J_pair J_c | r̃] and ∂r̃/∂d (header), robust-corrected,
  // into its pair's Gram matrix `gram`; its point's terms into `terms`. r̃ is `r` corrected,
  // or `kept_residual` where given (linearizeAt).
  void accumulate(const HostPatch<kN>& host, const PatchDerivatives<kN, K>& patch, int pair_index,
                  double d, const PatchResiduals& r, const RobustCorrection& correction,
                  const PatchResiduals* kept_residual, bool want_intrinsics, PairGram* gram,
                  ResidualTerms* terms) {
    const PhotometricPair& pair = pairs_[pair_index];
    Rows rows;
    Eigen::Matrix<double, kN, 1> J_d;
    for (int o = 0; o < kN; ++o) {
      const double sw = host.sqrt_weight[o];
      const Eigen::RowVector3d g = patch.d_r_d_x.row(o);
      const Eigen::Vector3d x = patch.point.row(o).transpose();
      // ε-columns = −(the target's tangent row of photometric_analytic.hpp).
      rows.template block<1, 3>(o, kEpsilon) = d * g;
      rows.template block<1, 3>(o, kEpsilon + 3) = -(g * skew(x));
      rows(o, kAlpha) = sw * pair.s * patch.host_term[o];
      rows(o, kGamma) = -sw;
      if (want_intrinsics)  // level 0: ∂c_L/∂c_0 = I
        rows.template block<1, K>(o, kPairIntrinsics) = patch.d_r_d_intrinsics.row(o);
      else
        rows.template block<1, K>(o, kPairIntrinsics).setZero();
      J_d[o] = g.dot(pair.t);
    }
    auto J = rows.template leftCols<kColumns>();
    correction.correctJacobian(r, J);
    correction.correctJacobian(r, J_d);
    auto r_corrected = rows.col(kColumns);
    if (kept_residual) {
      r_corrected = *kept_residual;
    } else {
      r_corrected = r;
      correction.correctResiduals(r_corrected);
    }

    addToLowerGram(Rows(rows), gram->lower, std::make_integer_sequence<int, (kGramSize + 1) / 2>{});
    gram->used = true;

    terms->point_hessian = J_d.squaredNorm();
    terms->point_gradient = J_d.dot(r_corrected);
    terms->v.noalias() = J_d.transpose() * J;
  }

  // h_p, g_p and row p of W: v through the pair's adjoint to the host, and to the target.
  void addToPoint(const ResidualTerms& terms, int pair_index, int p,
                  WindowNormalEquations* equations) const {
    const PhotometricPair& pair = pairs_[pair_index];
    const int h = pair_index / num_frames_, t = pair_index % num_frames_;
    equations->pointHessian(p) += terms.point_hessian;
    equations->pointGradient(p) += terms.point_gradient;
    const Eigen::Matrix<double, 1, kColumns>& v = terms.v;
    const Adjoint& adjoint = adjoints_[pair_index];
    auto w = equations->pointCoupling(p);
    const int host_offset = kFrameTangentSize * h, target_offset = kFrameTangentSize * t;
    w.template segment<6>(host_offset) += v.template segment<6>(kEpsilon) * adjoint;
    w[host_offset + 6] += v[kAlpha];
    w[host_offset + 7] -= pair.s * v[kGamma];  // β = −s γ
    w.template segment<6>(target_offset) -= v.template segment<6>(kEpsilon);
    w[target_offset + 6] -= v[kAlpha];
    w[target_offset + 7] += v[kGamma];
    w.template segment<K>(kFrameTangentSize * num_frames_) += v.template segment<K>(kPairIntrinsics);
  }

  // G += AᵀA, lower triangle only, two columns at a time (the last one alone when the size
  // is odd): half the products of the full AᵀA, in fixed-size blocks the compiler unrolls.
  // The window benchmark's 2-iteration solve: 0.83× the time of the full lazy product; 16
  // residuals collected per pair for one larger product were slower. The rows are passed as
  // a fresh copy: updating from the residual's own working matrix measured 1.2× slower
  // (docs/performance.md, "The native window solver").
  template <int... ColumnPair>
  static void addToLowerGram(const Rows& rows, Gram& G, std::integer_sequence<int, ColumnPair...>) {
    (addColumnsToLowerGram<2 * ColumnPair>(rows, G), ...);
  }
  template <int J>
  static void addColumnsToLowerGram(const Rows& rows, Gram& G) {
    constexpr int n = kGramSize - J, width = n < 2 ? n : 2;
    G.template block<n, width>(J, J).noalias() +=
        rows.template rightCols<n>().transpose().lazyProduct(rows.template middleCols<width>(J));
  }

  static Adjoint adjointOf(const PhotometricPair& pair) {
    Adjoint a = Adjoint::Zero();
    a.template topLeftCorner<3, 3>() = pair.R;
    a.template topRightCorner<3, 3>() = skew(pair.t) * pair.R;
    a.template bottomRightCorner<3, 3>() = pair.R;
    return a;
  }

  // [M_h M_t] of the header with β = −s γ folded in: pair columns [ε α γ] → [host pose,
  // host affine, target pose, target affine].
  static PairToFrames pairToFrames(const Adjoint& adjoint, double s) {
    PairToFrames m = PairToFrames::Zero();
    m.template block<6, 6>(kEpsilon, 0) = adjoint;
    m(kAlpha, 6) = 1.0;
    m(kGamma, 7) = -s;
    m.template block<6, 6>(kEpsilon, kFrameTangentSize) = -Adjoint::Identity();
    m(kAlpha, kFrameTangentSize + 6) = -1.0;
    m(kGamma, kFrameTangentSize + 7) = 1.0;
    return m;
  }

  void addPairsToFrames(const WindowProblem& problem, WindowNormalEquations* equations) const {
    const int num_frames = static_cast<int>(problem.frames.size());
    const int c = problem.intrinsicsOffset();
    Eigen::MatrixXd& H = equations->frameHessian();
    Eigen::VectorXd& g = equations->frameGradient();
    for (int h = 0; h < num_frames; ++h)
      for (int t = 0; t < num_frames; ++t) {
        const int pair = h * num_frames + t;
        if (h == t || !pair_grams_[pair].used) continue;
        const Gram G = pair_grams_[pair].lower.template selfadjointView<Eigen::Lower>();
        const PairToFrames M = pairToFrames(adjoints_[pair], pairs_[pair].s);
        const auto G_pair = G.template topLeftCorner<kPairIntrinsics, kPairIntrinsics>();
        const auto G_pair_c = G.template block<kPairIntrinsics, K>(0, kPairIntrinsics);
        const Eigen::Matrix<double, 16, 16> H_frames = M.transpose() * G_pair * M;
        const Eigen::Matrix<double, 16, K> H_frames_c = M.transpose() * G_pair_c;
        const Eigen::Matrix<double, 16, 1> g_frames =
            M.transpose() * G.template block<kPairIntrinsics, 1>(0, kColumns);
        const int offset[2] = {kFrameTangentSize * h, kFrameTangentSize * t};
        for (int a = 0; a < 2; ++a) {
          for (int b = 0; b < 2; ++b)
            H.block<kFrameTangentSize, kFrameTangentSize>(offset[a], offset[b]) +=
                H_frames.template block<kFrameTangentSize, kFrameTangentSize>(
                    kFrameTangentSize * a, kFrameTangentSize * b);
          H.block<kFrameTangentSize, K>(offset[a], c) +=
              H_frames_c.template middleRows<kFrameTangentSize>(kFrameTangentSize * a);
          H.block<K, kFrameTangentSize>(c, offset[a]) +=
              H_frames_c.template middleRows<kFrameTangentSize>(kFrameTangentSize * a).transpose();
          g.segment<kFrameTangentSize>(offset[a]) +=
              g_frames.template segment<kFrameTangentSize>(kFrameTangentSize * a);
        }
        H.block<K, K>(c, c) += G.template block<K, K>(kPairIntrinsics, kPairIntrinsics);
        g.segment<K>(c) += G.template block<K, 1>(kPairIntrinsics, kColumns);
      }
  }

  std::vector<HostBearings<kN, K>> bearings_;
  typename CameraD::VecN bearings_intrinsics_;
  bool bearings_have_jacobian_ = false;
  std::uint64_t bearings_problem_ = 0;  // WindowProblem::id they belong to
  int num_frames_ = 0;
  std::vector<PhotometricPair> pairs_;  // host-major, F × F
  std::vector<Adjoint> adjoints_;       // Ad(T_th) per pair
  std::vector<PairGram> pair_grams_;
  std::vector<int> pair_begin_, residuals_by_pair_, position_by_pair_, used_pairs_;
  std::vector<ResidualTerms> terms_;  // per residual, in residuals_by_pair_ order
  // What the evaluation at `current` leaves for the Jacobians at the first estimate
  // (evaluateAt), per residual in residuals_by_pair_ order.
  struct KeptEvaluation {
    bool valid = false;
    PatchResiduals raw_residuals;  // r
    PatchResiduals residuals;      // r̃, robust-corrected
    PatchImageGradients<kN> image_gradients;
  };
  std::vector<KeptEvaluation> kept_;
};

}  // namespace

template <template <typename> class Camera>
std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms() {
  return std::make_unique<PhotometricTermsOf<Camera>>();
}

template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<PinholeCamera>();
template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<UnifiedCamera>();
template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<ExtendedUnifiedCamera>();
template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<DoubleSphereCamera>();
template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<KannalaBrandtCamera>();
template std::unique_ptr<WindowPhotometricTerms> makeWindowPhotometricTerms<FovCamera>();

}  // namespace omnidso
