#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/activation_density.hpp>
#include <string>

namespace omnidso {

void validate(const ActivationDensityOptions& o) {
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(o.shrink_below) || !(o.shrink_below >= 0.0))
    throw Error("activation_density.shrink_below must be finite and >= 0, got " +
                std::to_string(o.shrink_below));
  if (!finite(o.step) || !(o.step > 0.0 && o.step <= 1.0))
    throw Error("activation_density.step must be in (0, 1], got " + std::to_string(o.step));
  if (!finite(o.min_scale) || !(o.min_scale >= 0.0 && o.min_scale <= 1.0))
    throw Error("activation_density.min_scale must be in [0, 1], got " +
                std::to_string(o.min_scale));
}

ActivationDensity::ActivationDensity(const ActivationDensityOptions& options)
    : options_(options) {
  validate(options_);
}

double ActivationDensity::update(int window_points, int num_points) {
  if (!options_.adaptive) return scale_;
  const double n = window_points, target = std::max(1, num_points);
  if (n < options_.shrink_below * target)
    scale_ = std::max(options_.min_scale, scale_ - options_.step);
  else
    scale_ = std::min(1.0, scale_ + options_.step);
  return scale_;
}

}  // namespace omnidso
