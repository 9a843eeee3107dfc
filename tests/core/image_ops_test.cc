#include "omnidso/core/image_ops.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "support/reference_image_preparation.hpp"

namespace omnidso {
namespace {

ImageF rampImage(int w, int h, float a, float b, float c) {
  ImageF img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = a * u + b * v + c;
  return img;
}

TEST(ImageOps, DownsamplePreservesMeanOnEvenSizes) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> intensity(0.0f, 255.0f);
  ImageF img(32, 18);
  double sum = 0;
  for (int v = 0; v < img.height(); ++v) {
    for (int u = 0; u < img.width(); ++u) {
      img(u, v) = intensity(rng);
      sum += img(u, v);
    }
  }
  const ImageF half = downsample2x2(img);
  ASSERT_EQ(half.width(), 16);
  ASSERT_EQ(half.height(), 9);
  double half_sum = 0;
  for (int v = 0; v < half.height(); ++v)
    for (int u = 0; u < half.width(); ++u) half_sum += half(u, v);
  // Each output pixel is a float mean of values ≤ 255: rounding ≤ ~3e-5 per pixel, far
  // less on average; the means agree to well within 1e-4.
  EXPECT_NEAR(half_sum / half.size(), sum / img.size(), 1e-4);
  EXPECT_FLOAT_EQ(half(2, 3), 0.25f * (img(4, 6) + img(5, 6) + img(4, 7) + img(5, 7)));
}

TEST(ImageOps, DownsampleOddSizesFloor) {
  const ImageF img(7, 5, 1.0f);
  const ImageF half = downsample2x2(img);
  EXPECT_EQ(half.width(), 3);
  EXPECT_EQ(half.height(), 2);
  const Mask mask_half = downsampleMask(Mask(7, 5, 255));
  EXPECT_EQ(mask_half.width(), 3);
  EXPECT_EQ(mask_half.height(), 2);
}

TEST(ImageOps, DownsampleMaskNeedsAllFourValid) {
  Mask mask(8, 6, 255);
  mask(5, 2) = 0;  // inside the block of coarse pixel (2, 1)
  const Mask half = downsampleMask(mask);
  for (int v = 0; v < half.height(); ++v)
    for (int u = 0; u < half.width(); ++u)
      EXPECT_EQ(half(u, v) != 0, !(u == 2 && v == 1)) << u << ", " << v;
}

TEST(ImageOps, GradientsExactOnLinearRampIncludingBorders) {
  const ImageF img = rampImage(9, 7, 3.0f, -2.0f, 100.0f);
  const ImageGradients g = computeGradients(img);
  const ImageF mag = gradientMagnitudeSquared(g);
  for (int v = 0; v < img.height(); ++v) {
    for (int u = 0; u < img.width(); ++u) {
      // Central and one-sided differences are exact for linear functions; the only error
      // is float rounding of values ≤ 130 (≈ 1e-5).
      EXPECT_NEAR(g.dx(u, v), 3.0f, 1e-4f);
      EXPECT_NEAR(g.dy(u, v), -2.0f, 1e-4f);
      EXPECT_NEAR(mag(u, v), 13.0f, 1e-3f);
    }
  }
}

TEST(ImageOps, GradientsCentralInsideOneSidedAtBorder) {
  ImageF img(4, 1);
  img(0, 0) = 0;
  img(1, 0) = 1;
  img(2, 0) = 4;
  img(3, 0) = 9;
  const ImageGradients g = computeGradients(img);
  EXPECT_FLOAT_EQ(g.dx(0, 0), 1.0f);  // I(1) − I(0)
  EXPECT_FLOAT_EQ(g.dx(1, 0), 2.0f);  // (I(2) − I(0)) / 2
  EXPECT_FLOAT_EQ(g.dx(2, 0), 4.0f);  // (I(3) − I(1)) / 2
  EXPECT_FLOAT_EQ(g.dx(3, 0), 5.0f);  // I(3) − I(2)
  EXPECT_FLOAT_EQ(g.dy(2, 0), 0.0f);  // a single row has no vertical gradient
}

// Bit for bit what the per-pixel formula gives (support/reference_image_preparation.hpp), on
// every size class: 1-pixel axes (zero derivative), 2-pixel axes (both one-sided), odd sizes,
// and a 480×480 image of random and of smooth rows (the borders and the inside of each).
bool sameBits(const ImageF& a, const ImageF& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(ImageOps, GradientsBitIdenticalToThePerPixelFormula) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> intensity(0.0f, 255.0f);
  const std::pair<int, int> sizes[] = {{1, 1}, {1, 7}, {7, 1}, {2, 2}, {2, 5}, {5, 2},
                                       {3, 3}, {31, 17}, {480, 480}};
  for (const auto& [w, h] : sizes) {
    ImageF noise(w, h), smooth(w, h);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        noise(u, v) = intensity(rng);
        smooth(u, v) = 100.0f + 60.0f * std::sin(0.07f * u) * std::cos(0.05f * v + 0.3f);
      }
    for (const ImageF* image : {&noise, &smooth}) {
      const ImageGradients fast = computeGradients(*image);
      const ImageGradients slow = reference::computeGradients(*image);
      EXPECT_TRUE(sameBits(fast.dx, slow.dx)) << w << "x" << h;
      EXPECT_TRUE(sameBits(fast.dy, slow.dy)) << w << "x" << h;
    }
  }
}

}  // namespace
}  // namespace omnidso
