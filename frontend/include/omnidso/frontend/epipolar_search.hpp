#pragma once
// Immature points and their inverse-distance search along the epipolar curve (paper Sec. V-B,
// eq. 9–12).
//
// A candidate pixel p of a keyframe starts with the inverse-distance interval [d_min, d_max] =
// [0, ∞) (Sec. V-C). For a tracked frame with [R t] = T_target_host and host bearing b = π⁻¹(p):
//   x̃(d) = R b + d t  ∝  R π⁻¹(p, d) + t                       (every central π is scale-free)
//   p_0 = π_s(x̃(d_min)),  p_∞ = π_s(x̃(d_max))   (π_s: onto the unit sphere; x̃(∞) ∝ t)  (eq. 9, 10)
//   p_L(s) = (1 − s) p_0 + s p_∞,   u_L(s) = π(p_L(s))                                      (eq. 11, 12)
// (s = 1 − α of the paper: the search runs from the far end d_min.) p_L(s) is a positive
// combination c_b(s) R b + c_t(s) t, so it lies on the exact epipolar curve, and the inverse
// distance it stands for is d(s) = c_t / c_b, increasing with s.
// The search steps s by δs = ‖∂u_L/∂s‖⁻¹ — one pixel — recomputed at every step (for the
// pinhole model the curve is DSO's straight line and δs is constant: one code path), over at
// most `max_search_px` pixels; steps where p_L leaves the model's domain or the pattern leaves
// the image are skipped. At each step the pattern SSD with affine brightness
//   E(s) = Σ_o ‖ I_j[u_L(s) + J_o o] − (a I_i[p + o] + b) ‖_γ,
//   J_o = ∂π/∂x (p_L(s)) · c_b R · ∂b/∂u    (the pattern's image in the target),
// is evaluated (Huber γ). The best step must beat the best one farther than 2 px from it by
// `min_quality` (DSO's ratio); Gauss–Newton on s then refines it to sub-pixel, and the interval
// becomes d(s* ± h δs), h pixels along the curve:
//   h = σ + e |c| / a,   a = lᵀ G l,  c = lᵀ G n,   G = J_o⁻ᵀ G_i J_o⁻¹,
// σ the matching uncertainty (`match_sigma_px`), l and n the unit tangent and normal of the
// curve at the match, G_i = Σ_o ∇I_i ∇I_iᵀ the host pattern's structure tensor and G its image
// in the target. Why: the tracked pose and the calibration are not exact, so the true curve
// lies some e pixels (`curve_offset_px`) across the one searched. Matching the pattern
// E(δ l + ε n) ≈ [δ ε] G [δ ε]ᵀ at a fixed offset ε puts the minimum at δ = −(c / a) ε: an
// offset turns into an error along the curve of tan α per pixel for a texture whose gradient
// makes the angle α with it (the geometric error DSO's search also bounds). Without this term
// such a match is as confident as a well-conditioned one and is activated at a wrong distance
// (docs/performance.md, "The search's interval from the pattern's gradients").

#include <Eigen/Core>
#include <array>
#include <limits>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/image_ops.hpp>
#include <omnidso/core/se3.hpp>

namespace omnidso {

inline constexpr int kImmaturePatternSize = 8;

enum class TraceStatus {
  kUninitialized,  // never traced
  kGood,           // matched; interval updated
  kSkipped,        // nothing to search: no translation, or a curve under `converged_px` (see trace)
  kOutOfBounds,    // no valid step on the curve (outside the image or the model's domain)
  kOutlier,        // best energy above the outlier threshold
  kBadCondition,   // ambiguous: best not clearly better than the second best
};
const char* toString(TraceStatus status);

struct ImmaturePoint {
  int host_id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // level 0
  Eigen::Vector3d bearing = Eigen::Vector3d::UnitZ();
  Eigen::Matrix<double, 3, 2> d_bearing_d_uv = Eigen::Matrix<double, 3, 2>::Zero();
  int pattern_spread = 1;  // the pattern's step in pixels (residual_pattern.hpp, spreadOffset)
  std::array<double, kImmaturePatternSize> host_intensity{};
  // G_i = Σ_o ∇I_i(p + o) ∇I_i(p + o)ᵀ over the pattern, in host pixels (header comment).
  Eigen::Matrix2d host_structure = Eigen::Matrix2d::Zero();
  double d_min = 0.0;                                       // inverse distance (far end)
  double d_max = std::numeric_limits<double>::infinity();   // (near end)
  double quality = 0.0;                                     // second-best / best energy
  double last_interval_px = std::numeric_limits<double>::infinity();
  TraceStatus last_status = TraceStatus::kUninitialized;
  int num_good_traces = 0;

  // The inverse distance to start the window optimisation from.
  double inverseDistanceEstimate() const;
};

// Creates an immature point at a level-0 pixel of a keyframe (host_gradients: the host image's,
// as ImagePyramid::gradients(0)), its pattern on steps of `pattern_spread` pixels; false when
// the pixel does not unproject or its pattern leaves the host image.
bool makeImmaturePoint(const Camera& camera, const ImageF& host_image,
                       const ImageGradients& host_gradients, int host_id,
                       const Eigen::Vector2d& pixel, ImmaturePoint* point,
                       int pattern_spread = 1);

struct EpipolarSearchOptions {
  double max_search_px = 26.0;    // DSO: 0.027 (w + h)
  double converged_px = 1.5;      // below this the interval is not searched again
  double min_quality = 3.0;       // best-to-second-best energy ratio
  double second_best_radius_px = 2.0;
  double outlier_energy_per_pixel = 12.0 * 12.0;
  double huber = 9.0;
  int gn_iterations = 3;
  double match_sigma_px = 0.75;   // σ: the new interval's half-width for a well-conditioned match
  // e: how far the true curve may lie across the searched one, pixels (header comment). 1 px:
  // on the development set's crops 0.25 / 0.5 / 1 / 2 px gave D3 medians 0.73 / 0.60 / 0.43 /
  // 0.42 % (0: 1.30 %); docs/performance.md.
  double curve_offset_px = 1.0;
  int max_domain_skips = 400;     // bounded walk over segments outside the model's domain
};

// Brightness of the target relative to the host: I_j ≈ a · I_i + b, with
// a = t_j e^{a_j} / (t_i e^{a_i}), b = b_j − a b_i (eq. 5).
struct AffineTransfer {
  double a = 1.0;
  double b = 0.0;
};

struct TraceResult {
  TraceStatus status = TraceStatus::kUninitialized;
  Eigen::Vector2d match = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double energy = 0.0;
  int steps = 0;
};

// Searches the point in a target image (level 0) and updates its interval, quality and status.
// target_content: where the target has content (ImagePyramid::content; nullptr: the whole
// image); a pattern sample touching a pixel without it is invalid, as one outside the image.
TraceResult traceImmaturePoint(ImmaturePoint& point, const Camera& camera,
                               const SE3d& T_target_host, const ImageF& target,
                               const ImageGradients& target_gradients,
                               const AffineTransfer& affine,
                               const EpipolarSearchOptions& options,
                               const Mask* target_content = nullptr);

}  // namespace omnidso
