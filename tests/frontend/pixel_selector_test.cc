// Candidate selection (pixel_selector.hpp) on a rendered fisheye image: what every selected
// pixel must satisfy, the count, and determinism.
#include <gtest/gtest.h>

#include <set>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

struct SelectionScene {
  Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  test::RenderedScene scene{camera, 5};
  ImagePyramid pyramid{scene.render(scene.centralPose()), 4};
  Mask mask = validityMask(camera);
};

float gradientNorm(const ImageGradients& g, int u, int v) {
  return std::sqrt(g.dx(u, v) * g.dx(u, v) + g.dy(u, v) * g.dy(u, v));
}

// Header, steps 1–2: a pixel selected on level L lies where its whole border neighbourhood is
// valid, and the level-L gradient norm over it exceeds 0.75^L × its block's threshold.
TEST(PixelSelector, EverySelectedPixelIsUsableAndPassesItsLevelsThreshold) {
  const SelectionScene s;
  PixelSelectorOptions options;
  options.desired_points = 1200;
  const std::vector<SelectedPixel> pixels = selectPixels(s.pyramid, s.mask, options);
  ASSERT_FALSE(pixels.empty());
  std::vector<Image<float>> norms;
  for (int level = 0; level < 3; ++level) {
    const ImageGradients& g = s.pyramid.gradients(level);
    Image<float> n(g.dx.width(), g.dx.height());
    for (int v = 0; v < n.height(); ++v)
      for (int u = 0; u < n.width(); ++u) n(u, v) = gradientNorm(g, u, v);
    norms.push_back(n);
  }
  const Image<float> thresholds = gradientThresholdMap(
      norms[0], s.mask, options.threshold_block_size, options.gradient_threshold_offset);
  int per_level[3] = {0, 0, 0};
  for (const SelectedPixel& p : pixels) {
    const int u = p.pixel.x(), v = p.pixel.y(), L = p.level;
    ASSERT_TRUE(L >= 0 && L < 3);
    ++per_level[L];
    for (int dv = -options.border; dv <= options.border; ++dv)
      for (int du = -options.border; du <= options.border; ++du)
        ASSERT_TRUE(s.mask(u + du, v + dv)) << "pixel (" << u << ", " << v << ")";
    const float factor = static_cast<float>(std::pow(options.coarser_level_factor, L));
    const float threshold = factor * thresholds(u / options.threshold_block_size,
                                                v / options.threshold_block_size);
    EXPECT_GT(norms[L](u >> L, v >> L), threshold) << "level " << L << " at (" << u << ", " << v << ")";
    EXPECT_FLOAT_EQ(p.gradient, norms[0](u, v));
  }
  EXPECT_GT(per_level[0], 0);
  // Step 3: the count adapts to within 20 % of the request (a textured room has enough).
  EXPECT_NEAR(static_cast<double>(pixels.size()), options.desired_points,
              0.2 * options.desired_points);
}

TEST(PixelSelector, TheSameSeedSelectsTheSamePixelsAnotherSeedOthers) {
  const SelectionScene s;
  PixelSelectorOptions options;
  options.desired_points = 800;
  auto selection = [&](std::uint64_t seed) {
    options.seed = seed;
    std::set<std::pair<int, int>> out;
    for (const SelectedPixel& p : selectPixels(s.pyramid, s.mask, options))
      out.insert({p.pixel.x(), p.pixel.y()});
    return out;
  };
  EXPECT_EQ(selection(3), selection(3));
  EXPECT_NE(selection(3), selection(4));  // the random directions differ per cell
}

TEST(PixelSelector, MaskOfAnotherSizeIsAnError) {
  const SelectionScene s;
  EXPECT_THROW(selectPixels(s.pyramid, Mask(10, 10, 255), PixelSelectorOptions{}), Error);
}

}  // namespace
}  // namespace omnidso
