// makeHostPatch's weights read in the camera's encoding (photometric_residual.hpp): with the
// host level's slope s = ∂I/∂E they are those the raw, encoded image would give — √w_E = s √w_I,
// so that √w_E r_E ≈ √w_I r_I — and without it they are not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "omnidso/core/error.hpp"
#include "omnidso/core/image_ops.hpp"
#include "omnidso/core/interpolation.hpp"
#include "omnidso/residuals/photometric_residual.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace omnidso {
namespace {

constexpr int kN = 8;
constexpr double kGamma = 1.0 / 2.2;  // I = G(E) = 255 (E/255)^γ

double encode(double e) { return 255.0 * std::pow(e / 255.0, kGamma); }
double encodeSlope(double e) { return kGamma * std::pow(e / 255.0, kGamma - 1.0); }

TEST(HostPatch, WeightsInTheCamerasEncodingAreTheRawImagesWeights) {
  const int w = 96, h = 80;
  ImageF energy(w, h), raw(w, h), slope(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      // Smooth texture, E from 20 to 160: dark parts get 2–3× the bright parts' slope.
      const double e = 90.0 + 70.0 * std::sin(0.13 * u) * std::cos(0.09 * v);
      energy(u, v) = static_cast<float>(e);
      raw(u, v) = static_cast<float>(encode(e));
      slope(u, v) = static_cast<float>(encodeSlope(e));
    }
  const ImageGradients energy_gradients = computeGradients(energy);
  const ImageGradients raw_gradients = computeGradients(raw);
  double largest_miss_without = 0.0;
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(20, 20), Eigen::Vector2d(47, 33), Eigen::Vector2d(70.4, 55.7),
        Eigen::Vector2d(30, 60)}) {
    const HostPatch<kN> in_encoding =
        makeHostPatch<kN>(energy, energy_gradients, pixel, kDsoGradientWeightC, &slope);
    const HostPatch<kN> linear = makeHostPatch<kN>(energy, energy_gradients, pixel);
    const HostPatch<kN> on_raw = makeHostPatch<kN>(raw, raw_gradients, pixel);
    for (int o = 0; o < kN; ++o) {
      const double u = pixel.x() + ResidualPattern<kN>::kOffsets[o].du;
      const double v = pixel.y() + ResidualPattern<kN>::kOffsets[o].dv;
      double e = 0.0;
      ASSERT_TRUE(sampleBilinearWithGradient(energy, u, v, &e, nullptr, nullptr));
      const double s = encodeSlope(e);
      // ∇I = s ∇E up to the central differences' second-order terms and the bilinear
      // sampling of s: well under 1 % on this texture.
      EXPECT_NEAR(in_encoding.sqrt_weight[o], s * on_raw.sqrt_weight[o],
                  0.01 * s * on_raw.sqrt_weight[o])
          << "pattern pixel " << o << " of (" << pixel.transpose() << ")";
      EXPECT_EQ(in_encoding.intensity[o], linear.intensity[o]);
      largest_miss_without = std::max(
          largest_miss_without,
          std::abs(linear.sqrt_weight[o] - s * on_raw.sqrt_weight[o]) / (s * on_raw.sqrt_weight[o]));
    }
  }
  EXPECT_GT(largest_miss_without, 0.3);  // the linear weights are not the encoding's
}

// A spread pattern samples the host at p + spread · o, records its spread, and refuses a spread
// below 1.
TEST(HostPatch, SpreadPatternSamplesOnItsSteps) {
  const int w = 64, h = 48;
  ImageF image(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) image(u, v) = static_cast<float>(3 * u + 100 * v);  // exact bilinear
  const ImageGradients gradients = computeGradients(image);
  const Eigen::Vector2d pixel(30.25, 20.5);
  const HostPatch<kN> patch = makeHostPatch<kN>(image, gradients, pixel, 50.0, nullptr, 3);
  EXPECT_EQ(patch.spread, 3);
  for (int o = 0; o < kN; ++o) {
    const PatternOffset offset = spreadOffset<kN>(o, 3);
    EXPECT_EQ(offset.du, 3 * ResidualPattern<kN>::kOffsets[o].du);
    EXPECT_NEAR(patch.intensity[o], 3 * (pixel.x() + offset.du) + 100 * (pixel.y() + offset.dv),
                1e-3)
        << "pattern pixel " << o;
  }
  EXPECT_THROW(makeHostPatch<kN>(image, gradients, pixel, 50.0, nullptr, 0), Error);
}

}  // namespace
}  // namespace omnidso
