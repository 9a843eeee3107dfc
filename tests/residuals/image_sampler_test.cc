#include "omnidso/residuals/image_sampler.hpp"

#include <gtest/gtest.h>

#include <random>

namespace omnidso {
namespace {

// The gradient choice reaches the hand-derived kernels' sampling and nothing else: the value
// (and the Jets' path) stays the bilinear one, the gradient is the interpolant's derivative by
// default and the blend of central differences on request — on a random texture the two
// differ at almost every position.
TEST(ImageSampler, TheGradientChoiceChangesTheGradientOnly) {
  std::mt19937 texture(3);
  std::uniform_real_distribution<float> intensity(0.0f, 255.0f);
  ImageF img(16, 12);
  for (int v = 0; v < 12; ++v)
    for (int u = 0; u < 16; ++u) img(u, v) = intensity(texture);
  Mask content(16, 12, 1);
  content(0, 5) = 0;
  const ImageSampler exact(img, ImageInterpolation::kBilinear, &content);
  const ImageSampler central(img, ImageInterpolation::kBilinear, &content,
                             ImageGradient::kCentralDifferences);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u_dist(0.0, 15.0), v_dist(0.0, 11.0);
  int differing = 0, valid = 0;
  for (int i = 0; i < 200; ++i) {
    const double u = u_dist(rng), v = v_dist(rng);
    double ve = 0, ge_u = 0, ge_v = 0, vc = 0, gc_u = 0, gc_v = 0, plain = 0;
    const bool ok = exact.sampleWithGradient(u, v, &ve, &ge_u, &ge_v);
    ASSERT_EQ(central.sampleWithGradient(u, v, &vc, &gc_u, &gc_v), ok);
    ASSERT_EQ(central.sample(u, v, &plain), ok);
    if (!ok) continue;
    ++valid;
    EXPECT_EQ(vc, ve);
    EXPECT_EQ(plain, ve);
    double ref = 0, ref_u = 0, ref_v = 0;
    ASSERT_TRUE(sampleBilinearWithGradient(img, u, v, &ref, &ref_u, &ref_v, &content));
    EXPECT_EQ(ge_u, ref_u);
    EXPECT_EQ(ge_v, ref_v);
    ASSERT_TRUE(sampleBilinearWithCentralGradient(img, u, v, &ref, &ref_u, &ref_v, &content));
    EXPECT_EQ(gc_u, ref_u);
    EXPECT_EQ(gc_v, ref_v);
    differing += gc_u != ge_u;
  }
  EXPECT_GT(valid, 150);
  EXPECT_GT(differing, valid * 9 / 10);
}

}  // namespace
}  // namespace omnidso
