// The renderer's photometric model; formulas in photometric_model.hpp.
#include <omnidso/synth/photometric_model.hpp>

#include <algorithm>
#include <cmath>

namespace omnidso::synth {

double PhotometricModel::response(double irradiance) const {
  const double x = std::clamp(irradiance / 255.0, 0.0, 1.0);
  return 255.0 * std::pow(x, 1.0 / gamma);
}

double PhotometricModel::inverseResponse(double pixel_value) const {
  const double x = std::clamp(pixel_value / 255.0, 0.0, 1.0);
  return 255.0 * std::pow(x, gamma);
}

double PhotometricModel::responseSlope(double irradiance) const {
  // d/dE 255 (E/255)^(1/γ) = (1/γ) (E/255)^(1/γ − 1)
  const double x = std::clamp(irradiance / 255.0, 1e-6, 1.0);
  return std::pow(x, 1.0 / gamma - 1.0) / gamma;
}

InverseResponse PhotometricModel::inverseResponseTable() const {
  InverseResponse table{};
  for (int k = 0; k < kResponseSize; ++k) table[static_cast<size_t>(k)] = inverseResponse(k);
  return table;
}

double PhotometricModel::noiseSigma(double irradiance) const {
  return std::sqrt(read_noise * read_noise + shot_noise * std::max(irradiance, 0.0));
}

double PhotometricModel::vignette(double u, double v, int width, int height, double cx,
                                  double cy) const {
  const double half_diagonal = 0.5 * std::hypot(width, height);
  const double r2 = ((u - cx) * (u - cx) + (v - cy) * (v - cy)) / (half_diagonal * half_diagonal);
  return std::max(0.05, 1.0 + vignette_r2 * r2 + vignette_r4 * r2 * r2);
}

double AutoExposure::next(double exposure_ms, double mean_pixel_value) const {
  const double ratio = target_mean / std::max(mean_pixel_value, 1.0);
  return std::clamp(exposure_ms * std::pow(ratio, rate), min_ms, max_ms);
}

}  // namespace omnidso::synth
