#pragma once
// How the camera encodes a corrected intensity: I = G(V E), E = G⁻¹(I)/V the intensity the
// odometry works on (photometric_calibration.hpp), G the response and V the vignette. Its
// slope,
//   s(p) = ∂I/∂E = G′(V(p) E(p)) · V(p),
// says how much of the encoding a change of E spans. Noise added after the response
// (quantisation, or an image pipeline's own noise) is uniform in I, so that σ_E = σ_I / s there:
// a dark or vignetted pixel's E is known more precisely than a bright one's. Noise from the
// sensor itself (read, shot) enters before the response and is uniform, or grows with E, in
// E. Two settings assume the first kind: pixel selection on gradients in the encoding,
// ‖∇I‖ ≈ s ‖∇E‖ (pixel_selector.hpp, `selection.camera_encoding`), and residuals weighed by
// s, r_I ≈ s r_E (photometric_residual.hpp, `noise_in_encoding`). Both are off by default
// (docs/performance.md, "Residuals weighed in the camera's encoding").

#include <vector>

#include "omnidso/core/image.hpp"

namespace omnidso {

class CameraEncoding {
 public:
  // response_slope: G′ at the raw values 0 … 255 (PhotometricCalibration::responseSlopeTable),
  // or empty for a linear response. vignette: V on the odometry's level-0 grid, or empty for
  // none; its pyramid (2×2 means, as ImagePyramid's) is built here, down to 2×2 pixels.
  CameraEncoding(std::vector<float> response_slope, const ImageF& vignette);

  // s per pixel of `intensity` (E on pyramid level `level`). Throws omnidso::Error when the
  // vignette has no such level or its size differs.
  ImageF slope(const ImageF& intensity, int level) const;
  // The check slope() makes, for an image of that size on that level.
  void checkLevel(int width, int height, int level) const;

  bool linear() const { return response_slope_.empty() && vignette_levels_.empty(); }

 private:
  std::vector<float> response_slope_;
  std::vector<ImageF> vignette_levels_;
};

}  // namespace omnidso
