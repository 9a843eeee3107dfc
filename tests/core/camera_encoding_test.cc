// CameraEncoding: s = ∂I/∂E = G′(V E) V of the encoding I = G(V E), per pixel and pyramid
// level, against the derivative of a gamma response; the sizes it refuses.
#include "omnidso/core/camera_encoding.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "omnidso/core/error.hpp"
#include "omnidso/core/image_ops.hpp"
#include "omnidso/core/photometric_calibration.hpp"

namespace omnidso {
namespace {

// G⁻¹(k) = 255 (k/255)^2.2 + k/255, a gamma with a small linear part (as in
// photometric_calibration_test.cc), so that G′ is finite at 0.
PhotometricCalibration gammaCalibration() {
  InverseResponse inverse;
  for (int k = 0; k < kResponseSize; ++k)
    inverse[k] = 255.0 * std::pow(k / 255.0, 2.2) + k / 255.0;
  return PhotometricCalibration(inverse, ImageF());
}

std::vector<float> slopeOf(const PhotometricCalibration& calib) {
  const auto table = calib.responseSlopeTable();
  return {table.begin(), table.end()};
}

// With V E on whole raw values the table is read where its test checked it: s/V is G′ there
// to the table's accuracy (photometric_calibration_test.cc, ResponseSlopeIsTheResponsesDerivative).
TEST(CameraEncoding, SlopeIsTheEncodingsDerivative) {
  const PhotometricCalibration calib = gammaCalibration();
  const int w = 64, h = 32;
  ImageF vignette(w, h), energy(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      vignette(u, v) = u < w / 2 ? 0.5f : 1.f;
      energy(u, v) = static_cast<float>(2 * ((u + 2 * v) % 120) + 4);  // V E whole, 2 … 243
    }
  const CameraEncoding encoding(slopeOf(calib), vignette);
  EXPECT_FALSE(encoding.linear());
  const ImageF s = encoding.slope(energy, 0);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double V = vignette(u, v);
      const double raw_energy = V * energy(u, v);
      const double i = calib.response(raw_energy);
      const double g_prime = 1.0 / (2.2 * std::pow(i / 255.0, 1.2) + 1.0 / 255.0);  // 1/(G⁻¹)′
      EXPECT_NEAR(s(u, v), g_prime * V, V * g_prime * 1.3 / std::max(i, 1.0))
          << "at (" << u << ", " << v << ")";
    }
}

// Level L reads the vignette's own pyramid (2×2 means, as the images'): a vignette of 0.5 on
// the left and 1 on the right stays so on level 1, and a linear response leaves s = V.
TEST(CameraEncoding, ReadsTheVignettesPyramidLevel) {
  const int w = 64, h = 32;
  ImageF vignette(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) vignette(u, v) = u < w / 2 ? 0.5f : 1.f;
  const CameraEncoding encoding({}, vignette);
  const ImageF level1 = downsample2x2(ImageF(w, h, 100.f));
  const ImageF s = encoding.slope(level1, 1);
  ASSERT_EQ(s.width(), w / 2);
  for (int v = 0; v < h / 2; ++v)
    for (int u = 0; u < w / 2; ++u) EXPECT_EQ(s(u, v), u < w / 4 ? 0.5f : 1.f);
  EXPECT_THROW(encoding.slope(level1, 0), Error);   // level 0's vignette is 64×32
  EXPECT_THROW(encoding.slope(level1, 40), Error);  // no such level
}

TEST(CameraEncoding, LinearWithoutCalibrationAndRefusesABadTable) {
  EXPECT_TRUE(CameraEncoding({}, ImageF()).linear());
  const ImageF s = CameraEncoding({}, ImageF()).slope(ImageF(4, 4, 50.f), 3);
  for (size_t i = 0; i < s.size(); ++i) EXPECT_EQ(s.data()[i], 1.f);
  EXPECT_THROW(CameraEncoding(std::vector<float>(255, 1.f), ImageF()), Error);
}

}  // namespace
}  // namespace omnidso
