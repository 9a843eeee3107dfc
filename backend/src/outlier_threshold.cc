#include "omnidso/backend/outlier_threshold.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "omnidso/core/error.hpp"

namespace omnidso {

double keyframeOutlierEnergy(std::vector<double>& energies, int pattern_size,
                             const OutlierThresholdOptions& options) {
  const auto finite_end = std::partition(energies.begin(), energies.end(),
                                         [](double e) { return std::isfinite(e); });
  const auto count = static_cast<size_t>(finite_end - energies.begin());
  if (count == 0) return 0.0;
  // The element at ⌊q n⌋ of the sorted energies (q < 1, so always one of them).
  const size_t index = std::min(count - 1, static_cast<size_t>(options.quantile * count));
  std::nth_element(energies.begin(), energies.begin() + static_cast<std::ptrdiff_t>(index),
                   finite_end);
  const double root_quantile = std::sqrt(std::max(0.0, energies[index]));
  const double root_fixed = std::sqrt(options.fixed_energy_per_pixel * pattern_size);
  const double root_bound = options.fixed_weight * root_fixed +
                            (1.0 - options.fixed_weight) * options.quantile_factor * root_quantile;
  return root_bound * root_bound;
}

void checkOutlierThresholdOptions(const OutlierThresholdOptions& options) {
  const auto fail = [](const char* what, double value) {
    throw Error(std::string("window.outlier_threshold.") + what + " (got " +
                std::to_string(value) + ")");
  };
  // Negated comparisons: NaN fails them too.
  if (!(options.quantile >= 0.0 && options.quantile < 1.0))
    fail("quantile must lie in [0, 1)", options.quantile);
  if (!(options.quantile_factor >= 0.0 && std::isfinite(options.quantile_factor)))
    fail("quantile_factor must be finite and >= 0", options.quantile_factor);
  if (!(options.fixed_weight >= 0.0 && options.fixed_weight <= 1.0))
    fail("fixed_weight must lie in [0, 1]", options.fixed_weight);
  if (!(options.fixed_energy_per_pixel >= 0.0 && std::isfinite(options.fixed_energy_per_pixel)))
    fail("fixed_energy_per_pixel must be finite and >= 0", options.fixed_energy_per_pixel);
}

}  // namespace omnidso
