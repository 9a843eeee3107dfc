#include "omnidso/core/pyramid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <tuple>
#include <vector>

#include "omnidso/core/error.hpp"
#include "support/reference_image_preparation.hpp"

namespace omnidso {
namespace {

ImageF rampImage(int w, int h, float a, float b) {
  ImageF img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = a * u + b * v;
  return img;
}

TEST(ImagePyramid, LevelSizesHalve) {
  const ImagePyramid pyramid(ImageF(64, 50, 1.0f));
  ASSERT_EQ(pyramid.numLevels(), ImagePyramid::kDefaultNumLevels);
  const int widths[] = {64, 32, 16, 8, 4};
  const int heights[] = {50, 25, 12, 6, 3};
  for (int l = 0; l < pyramid.numLevels(); ++l) {
    EXPECT_EQ(pyramid.level(l).width(), widths[l]);
    EXPECT_EQ(pyramid.level(l).height(), heights[l]);
    EXPECT_EQ(pyramid.gradients(l).dx.width(), widths[l]);
    EXPECT_EQ(pyramid.gradients(l).dy.height(), heights[l]);
  }
}

TEST(ImagePyramid, RampGradientDoublesPerLevel) {
  // A 2×2 mean of a linear ramp is the ramp at the block centre, 2u + 0.5 on the finer
  // level, so level L is again linear with slope 2^L·a — exact gradients, up to float
  // rounding of values ≤ 250 (≈ 2e-5, times the 2^L spacing at most ~4e-4).
  const float a = 1.25f, b = -0.5f;
  const ImagePyramid pyramid(rampImage(160, 96, a, b), 4);
  for (int l = 0; l < pyramid.numLevels(); ++l) {
    const float scale = static_cast<float>(1 << l);
    const ImageGradients& g = pyramid.gradients(l);
    for (int v = 0; v < g.dx.height(); ++v) {
      for (int u = 0; u < g.dx.width(); ++u) {
        ASSERT_NEAR(g.dx(u, v), a * scale, 1e-3f) << "level " << l;
        ASSERT_NEAR(g.dy(u, v), b * scale, 1e-3f) << "level " << l;
      }
    }
    // Pixel centre convention: level-L pixel u sits at level-0 (u + 0.5)·2^L − 0.5.
    const float u0 = (3 + 0.5f) * scale - 0.5f, v0 = (2 + 0.5f) * scale - 0.5f;
    EXPECT_NEAR(pyramid.level(l)(3, 2), a * u0 + b * v0, 1e-3f);
  }
}

TEST(ImagePyramid, LevelsAndGradientsBitIdenticalToThePerPixelFormulas) {
  // Every level and gradient as the 2×2 mean and central differences per pixel give them
  // (support/reference_image_preparation.hpp), on a 480×480 image of texture plus noise and
  // an odd-sized one whose levels drop a last column or row.
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> noise(-20.0f, 20.0f);
  for (const auto& [w, h, levels] : {std::tuple{480, 480, 4}, std::tuple{203, 151, 5}}) {
    ImageF image(w, h);
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u)
        image(u, v) = 120.0f + 80.0f * std::sin(0.11f * u + 0.02f * v) + noise(rng);
    const ImagePyramid pyramid(image, levels);
    const reference::Pyramid expected(image, levels);
    auto same = [](const ImageF& a, const ImageF& b) {
      return a.width() == b.width() && a.height() == b.height() &&
             std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
    };
    for (int l = 0; l < levels; ++l) {
      EXPECT_TRUE(same(pyramid.level(l), expected.levels[l])) << w << "x" << h << " level " << l;
      EXPECT_TRUE(same(pyramid.gradients(l).dx, expected.gradients[l].dx)) << "level " << l;
      EXPECT_TRUE(same(pyramid.gradients(l).dy, expected.gradients[l].dy)) << "level " << l;
    }
  }
}

TEST(ImagePyramid, TooSmallOrNoLevelsThrows) {
  EXPECT_THROW(ImagePyramid(ImageF(31, 64), 5), Error);  // 31/16 = 1 column at level 4
  EXPECT_NO_THROW(ImagePyramid(ImageF(32, 32), 5));
  EXPECT_THROW(ImagePyramid(ImageF(32, 32), 0), Error);
  EXPECT_THROW(ImagePyramid(ImageF(), 1), Error);
}

// A level is added while the current coarsest image has more than 5000 pixels (DSO's rule):
// 480×480 stops at 60×60 (3600 px, 4 levels), 640×480 at 80×60 (4800 px), 752×480 at 47×30
// (94×60 = 5640 px still halves), 1280×1024 at 40×32 (6 levels, the cap); max_levels caps.
// Odd sides halve with the floor: KITTI's 1241×376 reaches 77×23 (5 levels; 155×47 = 7285 px
// still halves), its 1226×370 76×23 (613×185 halves too) — DSO's rule stopped at an odd side,
// which gave them 1 and 2 levels and lost the initialisation.
TEST(PyramidLevelsForImage, CoarsestLevelKeepsEnoughPixels) {
  EXPECT_EQ(pyramidLevelsForImage(480, 480), 4);
  EXPECT_EQ(pyramidLevelsForImage(640, 480), 4);
  EXPECT_EQ(pyramidLevelsForImage(752, 480), 5);
  EXPECT_EQ(pyramidLevelsForImage(1280, 1024), 6);
  EXPECT_EQ(pyramidLevelsForImage(1280, 1024, 5000, 3), 3);
  EXPECT_EQ(pyramidLevelsForImage(481, 480), 4);
  EXPECT_EQ(pyramidLevelsForImage(1241, 376), 5);
  EXPECT_EQ(pyramidLevelsForImage(1226, 370), 5);
  EXPECT_EQ(pyramidLevelsForImage(960, 960), 5);
  EXPECT_EQ(pyramidLevelsForImage(60, 60), 1);
}

TEST(ImagePyramid, LevelOutOfRangeThrows) {
  const ImagePyramid pyramid(ImageF(16, 16), 2);
  EXPECT_THROW(pyramid.level(2), Error);
  EXPECT_THROW(pyramid.gradients(-1), Error);
}

// With the camera's encoding the pyramid keeps s = ∂I/∂E of every level, as
// CameraEncoding::slope computes it from that level; without, none.
TEST(ImagePyramid, KeepsTheEncodingsSlopeOfEveryLevel) {
  const ImageF image = rampImage(64, 48, 1.5f, 2.f);
  EXPECT_EQ(ImagePyramid(image, 3).encodingSlope(1), nullptr);
  std::vector<float> slope(256);
  for (int k = 0; k < 256; ++k) slope[k] = 2.f - k / 256.f;
  ImageF vignette(64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) vignette(u, v) = 1.f - 0.01f * u;
  const auto encoding = std::make_shared<const CameraEncoding>(slope, vignette);
  const ImagePyramid pyramid(image, 3, nullptr, encoding);
  for (int l = 0; l < 3; ++l) {
    const ImageF expected = encoding->slope(pyramid.level(l), l);
    const ImageF* kept = pyramid.encodingSlope(l);
    ASSERT_NE(kept, nullptr);
    ASSERT_EQ(kept->size(), expected.size());
    EXPECT_EQ(std::memcmp(kept->data(), expected.data(), expected.size() * sizeof(float)), 0);
  }
  EXPECT_THROW(pyramid.encodingSlope(3), Error);
  // A linear encoding keeps nothing: the residuals then weigh as without one.
  const auto linear = std::make_shared<const CameraEncoding>(std::vector<float>(), ImageF());
  EXPECT_EQ(ImagePyramid(image, 3, nullptr, linear).encodingSlope(0), nullptr);
  // A vignette of another size is refused when the pyramid is made, not at first use.
  const auto wrong = std::make_shared<const CameraEncoding>(slope, ImageF(32, 48, 1.f));
  EXPECT_THROW(ImagePyramid(image, 3, nullptr, wrong), Error);
}

}  // namespace
}  // namespace omnidso
