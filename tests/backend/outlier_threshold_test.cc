// keyframeOutlierEnergy (outlier_threshold.hpp): √θ = α √θ₀ + (1 − α) f √e_(q), worked by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>
#include <omnidso/backend/outlier_threshold.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

constexpr int kPattern = 8;

// Energies 8 i² (i = 0 … 9), shuffled: the 0.7-quantile is element ⌊0.7 · 10⌋ = 7 of the sorted
// ones, 8 · 49 = 392. With DSO's numbers √θ = 0.5 · 26 + 0.5 · 1.5 · √392.
std::vector<double> tenEnergies() {
  std::vector<double> e;
  for (int i : {3, 9, 0, 7, 5, 1, 8, 2, 6, 4}) e.push_back(8.0 * i * i);
  return e;
}

TEST(OutlierThreshold, BlendsTheFixedBoundWithTheQuantile) {
  std::vector<double> energies = tenEnergies();
  const double root = 0.5 * 26.0 + 0.5 * 1.5 * std::sqrt(392.0);
  EXPECT_NEAR(keyframeOutlierEnergy(energies, kPattern, OutlierThresholdOptions{}), root * root,
              1e-9 * root * root);
}

// Invalid residuals (infinite energy: out of the image) say nothing about the fit.
TEST(OutlierThreshold, IgnoresInvalidResiduals) {
  std::vector<double> plain = tenEnergies(), with_invalid = tenEnergies();
  const double inf = std::numeric_limits<double>::infinity();
  with_invalid.insert(with_invalid.begin() + 2, {inf, inf, inf});
  const OutlierThresholdOptions options;
  EXPECT_EQ(keyframeOutlierEnergy(with_invalid, kPattern, options),
            keyframeOutlierEnergy(plain, kPattern, options));
  std::vector<double> none = {inf, inf};
  EXPECT_EQ(keyframeOutlierEnergy(none, kPattern, options), 0.0);
  std::vector<double> empty;
  EXPECT_EQ(keyframeOutlierEnergy(empty, kPattern, options), 0.0);
}

// Without the fixed part the bound follows the residuals' scale: energies k² times larger
// (residuals k times larger, as from weights k times larger) give a bound k² times larger. The
// fixed part keeps it from falling below (α √θ₀)² on a perfect fit.
TEST(OutlierThreshold, FollowsTheResidualsScaleAboveItsFloor) {
  OutlierThresholdOptions options;
  options.fixed_weight = 0.0;
  std::vector<double> energies = tenEnergies(), scaled = tenEnergies();
  for (double& e : scaled) e *= 9.0;
  const double theta = keyframeOutlierEnergy(energies, kPattern, options);
  EXPECT_NEAR(keyframeOutlierEnergy(scaled, kPattern, options), 9.0 * theta, 1e-9 * theta);
  std::vector<double> perfect(10, 0.0);
  const OutlierThresholdOptions dso;
  const double floor = std::pow(0.5 * std::sqrt(26.0 * 26.0 / 8.0 * kPattern), 2);
  EXPECT_NEAR(keyframeOutlierEnergy(perfect, kPattern, dso), floor, 1e-9 * floor);
}

TEST(OutlierThreshold, RefusesSettingsOutsideTheirRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NO_THROW(checkOutlierThresholdOptions(OutlierThresholdOptions{}));
  for (double q : {-0.1, 1.0, nan}) {
    OutlierThresholdOptions o;
    o.quantile = q;
    EXPECT_THROW(checkOutlierThresholdOptions(o), Error) << q;
  }
  OutlierThresholdOptions o;
  o.fixed_weight = 1.5;
  EXPECT_THROW(checkOutlierThresholdOptions(o), Error);
  o = {};
  o.quantile_factor = -1.0;
  EXPECT_THROW(checkOutlierThresholdOptions(o), Error);
  o = {};
  o.fixed_energy_per_pixel = nan;
  EXPECT_THROW(checkOutlierThresholdOptions(o), Error);
}

}  // namespace
}  // namespace omnidso
