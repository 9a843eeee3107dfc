#pragma once
// Intrinsics on pyramid level L. Every model's parameters start [fx, fy, cx, cy]; the rest
// (ξ, α, β, k1.., distortion) act on normalised or angular coordinates and do not change.
// A level-L pixel averages 2^L × 2^L level-0 pixels (2×2 mean per level), and pixel centres
// sit at integer coordinates, so u_L = (u_0 + 0.5) / 2^L − 0.5:
//   fx_L = fx / 2^L,   cx_L = (cx + 0.5) / 2^L − 0.5   (likewise y).

#include <Eigen/Core>

namespace omnidso {

template <typename Derived>
void scaleIntrinsicsToLevel(Eigen::MatrixBase<Derived>& params, int level) {
  using Scalar = typename Derived::Scalar;
  const Scalar s = Scalar(1.0 / static_cast<double>(1 << level));
  params[0] *= s;
  params[1] *= s;
  params[2] = (params[2] + Scalar(0.5)) * s - Scalar(0.5);
  params[3] = (params[3] + Scalar(0.5)) * s - Scalar(0.5);
}

// Pixel coordinates between levels (same centre convention as above).
template <typename Scalar>
Scalar pixelToLevel(Scalar u0, int level) {
  return (u0 + Scalar(0.5)) / Scalar(1 << level) - Scalar(0.5);
}

}  // namespace omnidso
