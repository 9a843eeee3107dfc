#include "omnidso/core/interpolation.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace omnidso {
namespace {

ImageF randomImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> intensity(0.0f, 255.0f);
  ImageF img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = intensity(rng);
  return img;
}

// I(u, v) = a + b·u + c·v + d·u·v: bilinear interpolation reproduces any such function.
ImageF bilinearFunctionImage(int w, int h, double a, double b, double c, double d) {
  ImageF img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = static_cast<float>(a + b * u + c * v + d * u * v);
  return img;
}

TEST(Interpolation, ExactOnBilinearFunctions) {
  const double a = 7.0, b = 1.5, c = -0.75, d = 0.01;
  const ImageF img = bilinearFunctionImage(20, 15, a, b, c, d);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u_dist(0.0, 19.0), v_dist(0.0, 14.0);
  for (int i = 0; i < 200; ++i) {
    const double u = u_dist(rng), v = v_dist(rng);
    double value = 0, d_du = 0, d_dv = 0;
    ASSERT_TRUE(sampleBilinearWithGradient(img, u, v, &value, &d_du, &d_dv));
    // Pixels are float: |I| < 40 carries a rounding error below 40·2⁻²⁴ ≈ 2.4e-6, and a
    // convex combination (or a unit-spaced difference) of such values stays below 1e-5.
    EXPECT_NEAR(value, a + b * u + c * v + d * u * v, 1e-5);
    EXPECT_NEAR(d_du, b + d * v, 1e-5);
    EXPECT_NEAR(d_dv, c + d * u, 1e-5);
    double templated = 0;
    ASSERT_TRUE(sampleBilinear(img, u, v, &templated));
    EXPECT_NEAR(templated, value, 1e-12);  // same formula, same double arithmetic
  }
}

TEST(Interpolation, IntegerPositionsReturnPixels) {
  const ImageF img = randomImage(6, 5, 1);
  for (int v = 0; v < 5; ++v) {
    for (int u = 0; u < 6; ++u) {
      double value = -1;
      ASSERT_TRUE(sampleBilinear(img, double(u), double(v), &value));
      EXPECT_EQ(value, static_cast<double>(img(u, v)));  // weights are exactly 0 and 1
    }
  }
}

TEST(Interpolation, JetDerivativesEqualAnalyticGradient) {
  using Jet = ceres::Jet<double, 2>;
  const ImageF img = randomImage(12, 9, 7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u_dist(0.0, 11.0), v_dist(0.0, 8.0);
  for (int i = 0; i < 200; ++i) {
    // Include exact integers (cell edges), where both must pick the same one-sided cell.
    const double u = i % 10 == 0 ? std::floor(u_dist(rng)) : u_dist(rng);
    const double v = i % 7 == 0 ? std::floor(v_dist(rng)) : v_dist(rng);
    Jet value;
    ASSERT_TRUE(sampleBilinear(img, Jet(u, 0), Jet(v, 1), &value));
    double expected = 0, d_du = 0, d_dv = 0;
    ASSERT_TRUE(sampleBilinearWithGradient(img, u, v, &expected, &d_du, &d_dv));
    // Both evaluate the same polynomial in double; only the operation order differs.
    EXPECT_NEAR(value.a, expected, 1e-10);
    EXPECT_NEAR(value.v[0], d_du, 1e-10);
    EXPECT_NEAR(value.v[1], d_dv, 1e-10);
  }
}

TEST(Interpolation, GradientMatchesCentralDifferencesInsideCell) {
  const ImageF img = randomImage(10, 10, 11);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> frac(0.1, 0.9);  // stay ≥ h away from cell edges
  const double h = 1e-4;
  for (int i = 0; i < 100; ++i) {
    const double u = 2 + frac(rng), v = 5 + frac(rng);
    double value = 0, d_du = 0, d_dv = 0;
    ASSERT_TRUE(sampleBilinearWithGradient(img, u, v, &value, &d_du, &d_dv));
    double up = 0, um = 0, vp = 0, vm = 0;
    ASSERT_TRUE(sampleBilinear(img, u + h, v, &up));
    ASSERT_TRUE(sampleBilinear(img, u - h, v, &um));
    ASSERT_TRUE(sampleBilinear(img, u, v + h, &vp));
    ASSERT_TRUE(sampleBilinear(img, u, v - h, &vm));
    // Inside a cell the interpolant is linear along each axis, so the central difference
    // is exact up to rounding: ~ 2·eps·255 / (2h) ≈ 6e-10.
    EXPECT_NEAR((up - um) / (2 * h), d_du, 1e-8);
    EXPECT_NEAR((vp - vm) / (2 * h), d_dv, 1e-8);
  }
}

TEST(Interpolation, OutsideOrNonFiniteReturnsFalseAndLeavesValue) {
  const ImageF img = randomImage(8, 6, 2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const double outside[][2] = {{-1e-9, 2}, {7 + 1e-9, 2}, {3, -1e-9}, {3, 5 + 1e-9},
                               {nan, 2},   {3, nan},      {inf, 2},   {3, -inf}};
  for (const auto& p : outside) {
    double value = 123.0;
    EXPECT_FALSE(sampleBilinear(img, p[0], p[1], &value)) << p[0] << ", " << p[1];
    EXPECT_EQ(value, 123.0);
    EXPECT_FALSE(sampleBilinearWithGradient(img, p[0], p[1], &value, nullptr, nullptr));
    EXPECT_EQ(value, 123.0);
  }
  // The far corner itself is inside and returns that pixel.
  double corner = 0;
  ASSERT_TRUE(sampleBilinear(img, 7.0, 5.0, &corner));
  EXPECT_EQ(corner, static_cast<double>(img(7, 5)));
}

TEST(Interpolation, FloatInstantiationAgreesWithDouble) {
  const ImageF img = randomImage(8, 8, 9);
  float value_f = 0;
  double value_d = 0;
  ASSERT_TRUE(sampleBilinear(img, 3.3f, 4.6f, &value_f));
  ASSERT_TRUE(sampleBilinear(img, double(3.3f), double(4.6f), &value_d));
  // float arithmetic on values ≤ 255: a few ulps of 255 (≈ 1.5e-5 each).
  EXPECT_NEAR(value_f, value_d, 1e-4);
}

TEST(Interpolation, MaskNeedsAllFourNeighbours) {
  Mask mask(6, 6, 255);
  mask(3, 2) = 0;
  EXPECT_FALSE(isValidBilinear(mask, 2.5, 1.5));  // cells touching (3, 2)
  EXPECT_FALSE(isValidBilinear(mask, 3.5, 1.5));
  EXPECT_FALSE(isValidBilinear(mask, 2.5, 2.5));
  EXPECT_FALSE(isValidBilinear(mask, 3.5, 2.5));
  EXPECT_TRUE(isValidBilinear(mask, 1.5, 1.5));
  EXPECT_TRUE(isValidBilinear(mask, 4.5, 3.5));
  EXPECT_TRUE(isValidBilinear(mask, 5.0, 5.0));
  EXPECT_FALSE(isValidBilinear(mask, 5.01, 1.0));
  EXPECT_FALSE(isValidBilinear(mask, -0.01, 1.0));
}

// A content mask makes the samplers reject exactly the cells isValidBilinear rejects, leaving
// the value untouched, and returns the unmasked value everywhere else.
TEST(Interpolation, ContentMaskRejectsCellsTouchingNonContent) {
  const ImageF img = randomImage(6, 6, 4);
  Mask content(6, 6, 1);
  content(3, 2) = 0;
  for (double v = 0.0; v <= 5.0; v += 0.25)
    for (double u = 0.0; u <= 5.0; u += 0.25) {
      double plain = 0, masked = -7, masked_t = -7, d_du = 0, d_dv = 0;
      ASSERT_TRUE(sampleBilinear(img, u, v, &plain));
      const bool expected = isValidBilinear(content, u, v);
      EXPECT_EQ(sampleBilinear(img, u, v, &masked, &content), expected) << u << "," << v;
      EXPECT_EQ(sampleBilinearWithGradient(img, u, v, &masked_t, &d_du, &d_dv, &content), expected);
      EXPECT_EQ(masked, expected ? plain : -7.0);
      EXPECT_EQ(masked_t, expected ? plain : -7.0);
    }
}

// I(u, v) = a + b·u + c·v + q·(u² + v²): central differences are exact for a quadratic at
// every pixel, and their bilinear blend, linear in the position, is then the exact gradient
// b + 2qu everywhere inside (the border columns and rows, one-sided, are excluded). The
// interpolant's own derivative is the forward difference across the cell, b + q(2·u0 + 1):
// off by q(2·fu − 1), up to a quarter pixel's worth of curvature either way.
TEST(Interpolation, CentralGradientIsExactOnQuadraticsWhereTheInterpolantsIsNot) {
  const double a = 3.0, b = 0.5, c = -0.25, q = 0.02;
  ImageF img(24, 20);
  for (int v = 0; v < 20; ++v)
    for (int u = 0; u < 24; ++u) img(u, v) = static_cast<float>(a + b * u + c * v + q * (u * u + v * v));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u_dist(1.0, 22.0), v_dist(1.0, 18.0);
  double worst_interpolant = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double u = u_dist(rng), v = v_dist(rng);
    double value = 0, d_du = 0, d_dv = 0, plain = 0, i_du = 0, i_dv = 0;
    ASSERT_TRUE(sampleBilinearWithCentralGradient(img, u, v, &value, &d_du, &d_dv));
    ASSERT_TRUE(sampleBilinearWithGradient(img, u, v, &plain, &i_du, &i_dv));
    EXPECT_EQ(value, plain);  // the same bilinear value
    // |I| < 40: float pixels carry < 2.4e-6 each; a half-difference blend stays below 1e-5.
    EXPECT_NEAR(d_du, b + 2.0 * q * u, 1e-5);
    EXPECT_NEAR(d_dv, c + 2.0 * q * v, 1e-5);
    worst_interpolant = std::max(worst_interpolant, std::abs(i_du - (b + 2.0 * q * u)));
  }
  EXPECT_GT(worst_interpolant, 0.8 * q);  // the forward difference's offset, up to q
}

// The blend equals computeGradients' central-difference images blended bilinearly, borders
// (one-sided) included; where a neighbour has no content the difference turns one-sided
// away from it, so a fisheye's black surround never enters the gradient.
TEST(Interpolation, CentralGradientBlendsTheCentralDifferenceImagesAndStaysInsideTheContent) {
  const ImageF img = randomImage(9, 7, 5);
  ImageF gx(9, 7), gy(9, 7);
  for (int v = 0; v < 7; ++v)
    for (int u = 0; u < 9; ++u) {
      const int l = std::max(u - 1, 0), r = std::min(u + 1, 8), t = std::max(v - 1, 0),
                bo = std::min(v + 1, 6);
      gx(u, v) = static_cast<float>((double(img(r, v)) - img(l, v)) / (r - l));
      gy(u, v) = static_cast<float>((double(img(u, bo)) - img(u, t)) / (bo - t));
    }
  for (double v = 0.0; v <= 6.0; v += 0.5)
    for (double u = 0.0; u <= 8.0; u += 0.5) {
      double d_du = 0, d_dv = 0, ex = 0, ey = 0;
      ASSERT_TRUE(sampleBilinearWithCentralGradient(img, u, v, nullptr, &d_du, &d_dv));
      ASSERT_TRUE(sampleBilinear(gx, u, v, &ex));
      ASSERT_TRUE(sampleBilinear(gy, u, v, &ey));
      EXPECT_NEAR(d_du, ex, 1e-4) << u << "," << v;  // gx, gy rounded to float
      EXPECT_NEAR(d_dv, ey, 1e-4) << u << "," << v;
    }
  // Column 2 without content: at pixel (3, 3) the u-difference is I(4) − I(3), not
  // (I(4) − I(2)) / 2; the v-difference there is untouched.
  Mask content(9, 7, 1);
  for (int v = 0; v < 7; ++v) content(2, v) = 0;
  double d_du = 0, d_dv = 0;
  ASSERT_TRUE(sampleBilinearWithCentralGradient(img, 3.0, 3.0, nullptr, &d_du, &d_dv, &content));
  EXPECT_NEAR(d_du, double(img(4, 3)) - img(3, 3), 1e-9);
  EXPECT_NEAR(d_dv, (double(img(3, 4)) - img(3, 2)) / 2.0, 1e-9);
  EXPECT_FALSE(sampleBilinearWithCentralGradient(img, 2.5, 3.0, nullptr, &d_du, &d_dv, &content));
}

}  // namespace
}  // namespace omnidso
