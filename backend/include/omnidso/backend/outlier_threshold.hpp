#pragma once
// A keyframe's outlier bound, measured from the window's own residuals (the original DSO's
// per-frame energy threshold; its code sets it, its paper does not describe it). A fixed
// bound per pixel, 12², ignores how well a given camera, scene and frame match, and how the
// residuals are weighed: the same bound is strict for a noisy frame and lax for a clean one.
// Measured from the energies e_i of the residuals observed in keyframe k while k is the
// newest keyframe of the window (their typical fit to it):
//
//   √θ_k = α √θ₀ + (1 − α) f √e_(q),
//
// with e_(q) the q-quantile of those energies (a residual is a whole pattern, the energy its
// sum over the pattern), √θ₀ a fixed part that keeps the bound from collapsing on a perfect
// fit, f a margin over the quantile and α the blend. With DSO's numbers (q = 0.7, f = 1.5,
// α = 0.5, θ₀ = 26² for its 8-pixel pattern) a keyframe whose residuals stay below 6² per
// pixel in 70 % of cases bounds them at ≈ 9.1² per pixel, rather than 12². A residual between
// host h and target t is an outlier above max(θ_h, θ_t) (DSO likewise); a keyframe that was
// never the newest with residuals has no θ of its own.

#include <vector>

namespace omnidso {

struct OutlierThresholdOptions {
  bool adaptive = false;  // false: the fixed bound (WindowOptions::outlier_energy_per_pixel)
  double quantile = 0.7;  // q
  double quantile_factor = 1.5;  // f
  double fixed_weight = 0.5;  // α
  double fixed_energy_per_pixel = 26.0 * 26.0 / 8.0;  // θ₀ per pattern pixel (DSO: 26² per 8)
};

// θ for a pattern of `pattern_size` pixels from the newest keyframe's residual energies
// (finite ones; infinite, i.e. invalid, ones are ignored). Returns 0 when none is finite
// (no bound measured). `energies` is reordered.
double keyframeOutlierEnergy(std::vector<double>& energies, int pattern_size,
                             const OutlierThresholdOptions& options);

// Throws omnidso::Error naming the setting unless 0 ≤ q < 1, f ≥ 0, 0 ≤ α ≤ 1 and θ₀ ≥ 0.
void checkOutlierThresholdOptions(const OutlierThresholdOptions& options);

}  // namespace omnidso
