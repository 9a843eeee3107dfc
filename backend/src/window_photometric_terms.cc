// The photometric residuals of the native window solver (window_photometric_terms.hpp): the
// kernel of residuals/photometric_kernel.hpp per (point, target) residual, the Jacobian in
// relative-pose form, JᵀJ summed per host–target pair and per point, and the pairs mapped
// to the frames' blocks. Instantiated for every camera model with a residual kernel.
#include <omnidso/backend/robust_correction.hpp>
#include <omnidso/backend/window_normal_equations.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/cameras/double_sphere.hpp>
#include <omnidso/cameras/extended_unified.hpp>
#include <omnidso/cameras/kannala_brandt.hpp>
#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/cameras/unified.hpp>
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

 public:
  double evaluate(const WindowProblem& problem, WindowNormalEquations* equations,
                  std::vector<double>* energies) override {
    const int num_frames = num_frames_ = static_cast<int>(problem.frames.size());
    typename CameraD::VecN intrinsics = Eigen::Map<const typename CameraD::VecN>(problem.intrinsics);
    scaleIntrinsicsToLevel(intrinsics, 0);  // as the cost function does (level 0)
    const CameraD camera(intrinsics);
    const bool want_intrinsics = equations && !problem.intrinsics_constant;
    refreshBearings(problem, camera, intrinsics);

    std::vector<ImageSampler> samplers;
    samplers.reserve(num_frames);
    for (const WindowFrame& f : problem.frames)
      samplers.emplace_back(*f.image, problem.interpolation, f.content);
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
    if (equations) {
      pair_grams_.resize(pairs_.size());
      for (PairGram& g : pair_grams_) {
        g.lower.setZero();
        g.used = false;
      }
    }

    // OutOfBoundsPenalty's constant residual √(E/N) per pixel.
    const Eigen::Matrix<double, kN, 1> penalty =
        Eigen::Matrix<double, kN, 1>::Constant(std::sqrt(problem.out_of_bounds_energy / kN));
    const double invalid_cost = RobustCorrection(problem.photometric_loss, penalty.squaredNorm()).cost();

    if (energies) energies->resize(problem.residuals.size());
    double cost = 0.0;
    Eigen::Matrix<double, kN, 1> r;
    PatchDerivatives<kN, K> patch;
    for (int p = 0; p < static_cast<int>(problem.points.size()); ++p) {
      const WindowPointBlock& point = problem.points[p];
      const double d = *point.inverse_distance;
      for (int k = point.first_residual; k < point.first_residual + point.num_residuals; ++k) {
        const int h = point.host, t = problem.residuals[k].target;
        const int pair = h * num_frames + t;
        const PhotometricStatus status = evaluatePhotometricPatch(
            camera, samplers[t], *point.patch, bearings_[p], pairs_[pair], d, r.data(),
            equations ? &patch : nullptr, want_intrinsics);
        if (status != PhotometricStatus::kValid) {
          cost += invalid_cost;  // and a zero Jacobian: nothing to accumulate
          if (energies) (*energies)[k] = std::numeric_limits<double>::infinity();
          continue;
        }
        if (energies) (*energies)[k] = r.squaredNorm();
        const RobustCorrection correction(problem.photometric_loss, r.squaredNorm());
        cost += correction.cost();
        if (equations)
          accumulate(*point.patch, patch, pair, d, r, correction, p, want_intrinsics, equations);
      }
    }
    if (equations) addPairsToFrames(problem, equations);
    return cost;
  }

 private:
  // b_o (and ∂b_o/∂c when the intrinsics are variable) per point, kept while the
  // intrinsics are the same.
  void refreshBearings(const WindowProblem& problem, const CameraD& camera,
                       const typename CameraD::VecN& intrinsics) {
    const bool with_jacobian = !problem.intrinsics_constant;
    if (bearings_.size() == problem.points.size() && bearings_intrinsics_ == intrinsics &&
        (bearings_have_jacobian_ || !with_jacobian))
      return;
    bearings_.resize(problem.points.size());
    for (size_t p = 0; p < problem.points.size(); ++p)
      unprojectHostPattern(camera, *problem.points[p].patch, with_jacobian, &bearings_[p]);
    bearings_intrinsics_ = intrinsics;
    bearings_have_jacobian_ = with_jacobian;
  }

  // One valid residual: its rows [J_pair J_c | r̃] and ∂r̃/∂d (header), robust-corrected,
  // into the pair's Gram matrix and into point p's h_p, g_p and row of W.
  void accumulate(const HostPatch<kN>& host, const PatchDerivatives<kN, K>& patch, int pair_index,
                  double d, const Eigen::Matrix<double, kN, 1>& r,
                  const RobustCorrection& correction, int p, bool want_intrinsics,
                  WindowNormalEquations* equations) {
    const PhotometricPair& pair = pairs_[pair_index];
    const int h = pair_index / num_frames_, t = pair_index % num_frames_;
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
    r_corrected = r;
    correction.correctResiduals(r_corrected);

    addToLowerGram(Rows(rows), pair_grams_[pair_index].lower,
                   std::make_integer_sequence<int, (kGramSize + 1) / 2>{});
    pair_grams_[pair_index].used = true;

    equations->pointHessian(p) += J_d.squaredNorm();
    equations->pointGradient(p) += J_d.dot(r_corrected);
    const Eigen::Matrix<double, 1, kColumns> v = J_d.transpose() * J;
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
  int num_frames_ = 0;
  std::vector<PhotometricPair> pairs_;  // host-major, F × F
  std::vector<Adjoint> adjoints_;       // Ad(T_th) per pair
  std::vector<PairGram> pair_grams_;
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

}  // namespace omnidso
