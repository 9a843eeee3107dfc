#pragma once
// The ground-truth photometric model of the renderer (the model of
// omnidso/core/photometric_calibration.hpp, which reads what the dataset writer stores):
//   I(x) = G(E(x) + n),   E(x) = gain · t · V(x) · B(x)
// with B the scene radiance in [0, 1] (texture.hpp), t the exposure time in ms, V the
// vignette, G the response and n sensor noise (all defined here):
//   G(E) = 255 · (E/255)^(1/γ)                        (gamma-like, monotone; E ∈ [0, 255])
//   G⁻¹(k) = 255 · (k/255)^γ                          (written as pcalib.txt, k = 0..255)
//   V(x) = 1 + v₁ r² + v₂ r⁴,  r = ‖x − c‖ / half image diagonal     (radial falloff)
//   n ~ N(0, σ_read² + κ·E)                           (read noise + shot-like noise)
// The pixel is round(clamp(G(E + n), 0, 255)). V is 0 where the camera sees nothing
// (outside a fisheye's image circle): the vignette image doubles as the validity mask.

#include <vector>

#include <omnidso/core/image.hpp>
#include <omnidso/core/photometric_calibration.hpp>

namespace omnidso::synth {

struct PhotometricModel {
  double gamma = 1.6;             // G⁻¹(k) = 255 (k/255)^γ
  double gain_per_ms = 255.0 / 20.0;  // E = gain · t[ms] · V · B: B = 1, V = 1, t = 20 ms saturates
  double vignette_r2 = -0.6;      // v₁
  double vignette_r4 = 0.1;       // v₂ (V(1) = 0.5, monotone on [0, 1])
  double read_noise = 0.6;        // σ_read, irradiance units (0..255 scale)
  double shot_noise = 0.04;       // κ
  bool noise = true;

  double response(double irradiance) const;         // G, clamped to [0, 255]
  double inverseResponse(double pixel_value) const;  // G⁻¹
  // dG/dE, for error propagation in tests.
  double responseSlope(double irradiance) const;
  InverseResponse inverseResponseTable() const;  // G⁻¹(0..255) for pcalib.txt
  double noiseSigma(double irradiance) const;    // √(σ_read² + κ E)

  // V at pixel (u, v) of a width × height image with the optical centre (cx, cy).
  double vignette(double u, double v, int width, int height, double cx, double cy) const;
};

// Auto-exposure like a camera's: after each frame the exposure moves toward the value that
// would bring the mean pixel value of the valid image to the target,
//   t ← clamp(t · (target/mean)^rate, t_min, t_max),
// a damped multiplicative controller (rate < 1 makes the change smooth over frames).
struct AutoExposure {
  double target_mean = 105.0;
  double rate = 0.25;
  double min_ms = 1.0;
  double max_ms = 30.0;
  double next(double exposure_ms, double mean_pixel_value) const;
};

}  // namespace omnidso::synth
