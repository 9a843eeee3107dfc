// The content margin (odometry.hpp, defaultContentMarginPx): the level-0 pixels it keeps host
// patches whose every value and weight are independent of what lies outside the content, and
// no smaller margin does that. A larger one only takes the image circle's rim away: at
// 2^levels + 3 a fifth of a 120° circle's radius, and runs lost their scale in a fast turn
// (docs/performance.md, "A 120° image circle in a fast turn").
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/residuals/photometric_residual.hpp>
#include <random>

namespace omnidso {
namespace {

constexpr int kSize = 96;

// Content in a square inside the image: straight edges, which DSO's pattern meets with its
// longest arms (a disc's curve keeps the erosion's corners off them).
Mask square() {
  Mask m(kSize, kSize);
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) m(u, v) = u >= 20 && u < 76 && v >= 20 && v < 76;
  return m;
}

// A textured scene in the content; outside it, black or noise.
ImageF scene(const Mask& content, bool noise_outside) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.f, 255.f);
  ImageF image(kSize, kSize);
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) {
      const float outside = noise_outside ? uniform(rng) : 0.f;
      image(u, v) = content(u, v) ? static_cast<float>(128.0 + 60.0 * std::sin(0.7 * u) *
                                                                    std::cos(0.45 * v))
                                  : outside;
    }
  return image;
}

// Level-0 pixels kept by `margin` whose host patch (DSO's pattern on steps of `spread`) differs
// between the two surrounds.
int patchesTouchingTheSurround(int margin, int spread) {
  const Mask content = square();
  const ImagePyramid black(scene(content, false), 1), noisy(scene(content, true), 1);
  const Mask kept = erodeContent(content, margin);
  int touching = 0, checked = 0;
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u) {
      const Eigen::Vector2d pixel(u, v);
      if (!kept(u, v) || !hostPatchFits<kWindowPatternSize>(black.level(0), pixel, spread))
        continue;
      ++checked;
      const auto a = makeHostPatch<kWindowPatternSize>(black.level(0), black.gradients(0), pixel,
                                                       kDsoGradientWeightC, nullptr, spread);
      const auto b = makeHostPatch<kWindowPatternSize>(noisy.level(0), noisy.gradients(0), pixel,
                                                       kDsoGradientWeightC, nullptr, spread);
      bool same = true;
      for (int o = 0; o < kWindowPatternSize; ++o)
        same = same && a.intensity[o] == b.intensity[o] && a.sqrt_weight[o] == b.sqrt_weight[o];
      touching += !same;
    }
  EXPECT_GT(checked, 0) << "margin " << margin << " left no pixel to check";
  return touching;
}

TEST(ContentMargin, KeepsEveryLevelZeroHostPatchOffTheSurroundAndIsTheSmallestThatDoes) {
  for (int spread : {1, 2, 3}) {
    const int margin = defaultContentMarginPx(spread);
    EXPECT_EQ(patchesTouchingTheSurround(margin, spread), 0) << "spread " << spread;
    EXPECT_GT(patchesTouchingTheSurround(margin - 1, spread), 0) << "spread " << spread;
  }
}

}  // namespace
}  // namespace omnidso
