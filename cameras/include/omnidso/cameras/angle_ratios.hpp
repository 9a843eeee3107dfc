#pragma once
// Ratios of an angle α's sine and cosine that radial camera models (KB4 in θ, FOV in φ) need
// near the optical axis, where their direct forms divide zero by zero or cancel. Each takes
// sin α and cos α from the caller, who often has them without a call to sin or cos.
//   sinc α                    = sin α/α                    → 1
//   (α − sin α cos α)/α³      = (2α − sin 2α)/(2α³)        → 2/3
//   (α cos α − sin α)/α³                                   → −1/3
// Templates on the scalar (double, float, ceres::Jet), for α ≥ 0.

namespace omnidso {

// Below α = 1e-4 the series 1 − α²/6, whose next term α⁴/120 is under 1e-18.
template <typename Scalar>
Scalar sinc(const Scalar& alpha, const Scalar& sin_alpha) {
  if (alpha < Scalar(1e-4)) return Scalar(1) - alpha * alpha / Scalar(6);
  return sin_alpha / alpha;
}

// The direct form cancels (error ε/α²), so below α = 0.1 the series 2/3 − 2α²/15 + 4α⁴/315 −
// 2α⁶/2835 + 4α⁸/155925 (next term under 1e-16 there).
template <typename Scalar>
Scalar angleMinusSinCosOverCube(const Scalar& alpha, const Scalar& sin_alpha,
                                const Scalar& cos_alpha) {
  const Scalar a2 = alpha * alpha;
  if (alpha < Scalar(0.1)) {
    return Scalar(2.0 / 3.0) +
           a2 * (Scalar(-2.0 / 15.0) +
                 a2 * (Scalar(4.0 / 315.0) +
                       a2 * (Scalar(-2.0 / 2835.0) + a2 * Scalar(4.0 / 155925.0))));
  }
  return (alpha - sin_alpha * cos_alpha) / (a2 * alpha);
}

// Series −1/3 + α²/30 − α⁴/840 + α⁶/45360 − α⁸/3991680 below α = 0.1.
template <typename Scalar>
Scalar angleCosMinusSinOverCube(const Scalar& alpha, const Scalar& sin_alpha,
                                const Scalar& cos_alpha) {
  const Scalar a2 = alpha * alpha;
  if (alpha < Scalar(0.1)) {
    return Scalar(-1.0 / 3.0) +
           a2 * (Scalar(1.0 / 30.0) +
                 a2 * (Scalar(-1.0 / 840.0) +
                       a2 * (Scalar(1.0 / 45360.0) + a2 * Scalar(-1.0 / 3991680.0))));
  }
  return (alpha * cos_alpha - sin_alpha) / (a2 * alpha);
}

}  // namespace omnidso
