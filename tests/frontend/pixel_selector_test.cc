// Candidate selection (pixel_selector.hpp) on a rendered fisheye image: what every selected
// pixel must satisfy, the count, and determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <random>
#include <set>
#include <omnidso/core/error.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/reference_selection.hpp"
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

// The selection is bit-identical to the straightforward one it replaced
// (support/reference_selection.hpp): the same pixels in the same order, the same levels, the
// same gradient bits. Over masks whose outline and inside differ (scattered invalid pixels:
// the usable rule tests the square's outline only), no mask, an odd-sized crop (the coarser
// levels' last column and row are clamped), a 2-level pyramid, and options that move the
// cell size, the blocks (not a multiple of 4) and the border.
void expectSameSelection(const ImagePyramid& pyramid, const Mask& mask,
                         const PixelSelectorOptions& options, const std::string& what) {
  const std::vector<SelectedPixel> fast = selectPixels(pyramid, mask, options);
  const std::vector<SelectedPixel> slow = reference::selectPixels(pyramid, mask, options);
  ASSERT_EQ(fast.size(), slow.size()) << what;
  ASSERT_FALSE(fast.empty()) << what;
  for (size_t i = 0; i < fast.size(); ++i) {
    ASSERT_EQ(fast[i].pixel, slow[i].pixel) << what << ", pixel " << i;
    ASSERT_EQ(fast[i].level, slow[i].level) << what << ", pixel " << i;
    ASSERT_EQ(std::memcmp(&fast[i].gradient, &slow[i].gradient, sizeof(float)), 0) << what;
  }
}

Mask withScatteredHoles(const Mask& mask, double fraction, std::uint64_t seed) {
  Mask out = mask.empty() ? Mask(320, 320, 255) : mask;
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution hole(fraction);
  for (size_t i = 0; i < out.size(); ++i)
    if (hole(rng)) out.data()[i] = 0;
  return out;
}

TEST(PixelSelector, SelectsBitIdenticallyToTheReference) {
  const SelectionScene s;
  const std::vector<std::pair<std::string, Mask>> masks = {
      {"fisheye mask", s.mask},
      {"no mask", Mask()},
      {"holes 0.2 %", withScatteredHoles(s.mask, 0.002, 1)},
      {"holes 2 %", withScatteredHoles(s.mask, 0.02, 2)}};
  for (const auto& [name, mask] : masks)
    for (int desired : {150, 800, 2000, 20000})
      for (std::uint64_t seed : {0u, 7u}) {
        PixelSelectorOptions options;
        options.desired_points = desired;
        options.seed = seed;
        expectSameSelection(s.pyramid, mask, options,
                            name + ", " + std::to_string(desired) + " points, seed " +
                                std::to_string(seed));
      }
  PixelSelectorOptions odd;
  odd.threshold_block_size = 21;
  odd.border = 2;
  odd.coarser_level_factor = 0.6;
  expectSameSelection(s.pyramid, masks[2].second, odd, "block 21, border 2");
  odd.border = 0;
  expectSameSelection(s.pyramid, masks[3].second, odd, "border 0");
}

TEST(PixelSelector, SelectsBitIdenticallyToTheReferenceOnOddSizesAndFewLevels) {
  const SelectionScene s;
  const int w = 301, h = 263;  // level 1 is 150×131: column 300 and row 262 clamp to it
  ImageF crop(w, h);
  Mask mask(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      crop(u, v) = s.pyramid.level(0)(u + 10, v + 30);
      mask(u, v) = s.mask(u + 10, v + 30);
    }
  PixelSelectorOptions options;
  options.desired_points = 900;
  options.border = 1;
  expectSameSelection(ImagePyramid(crop, 3), mask, options, "301x263, 3 levels");
  expectSameSelection(ImagePyramid(crop, 2), Mask(), options, "301x263, 2 levels");
  expectSameSelection(ImagePyramid(crop, 1), withScatteredHoles(mask, 0.01, 3), options,
                      "301x263, 1 level");
}

// The block medians are found by a radix select on the float bits, not nth_element: the same
// bits on gradient norms (ties, zeros, denormals, +∞, blocks cut by the image edge and the
// mask), and — through its fallback — on values outside that order (negative, −0).
TEST(PixelSelector, ThresholdMapBitIdenticalToTheReference) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> value(0.0f, 300.0f);
  std::uniform_int_distribution<int> pick(0, 99);
  const float specials[] = {0.0f, 1e-40f, 7.0f, std::numeric_limits<float>::infinity()};
  for (const bool unordered : {false, true}) {
    Image<float> norm(203, 150);
    for (size_t i = 0; i < norm.size(); ++i) {
      const int p = pick(rng);
      norm.data()[i] = p < 20 ? specials[p % 4] : std::round(value(rng) * (p < 50 ? 1 : 64)) / 64;
      if (unordered && p == 99) norm.data()[i] = -0.0f;
      if (unordered && p == 98) norm.data()[i] = -3.0f;
    }
    const Mask holes = withScatteredHoles(Mask(203, 150, 255), 0.3, 5);
    for (const Mask& mask : {Mask(), holes})
      for (int block : {32, 7}) {
        const Image<float> fast = gradientThresholdMap(norm, mask, block, 7.0);
        const Image<float> slow = reference::gradientThresholdMap(norm, mask, block, 7.0);
        ASSERT_EQ(fast.width(), slow.width());
        ASSERT_EQ(fast.height(), slow.height());
        EXPECT_EQ(std::memcmp(fast.data(), slow.data(), fast.size() * sizeof(float)), 0)
            << "block " << block << ", mask " << !mask.empty() << ", unordered " << unordered;
      }
  }
}

TEST(PixelSelector, MaskOfAnotherSizeIsAnError) {
  const SelectionScene s;
  EXPECT_THROW(selectPixels(s.pyramid, Mask(10, 10, 255), PixelSelectorOptions{}), Error);
}


// PixelSelectorOptions::encoding, the response's part. A gamma-encoded camera's dark half and bright half
// with the same raw texture (±25 grey values about 60 and 180): in the corrected, linear
// intensities E = G⁻¹(I) the bright half's gradients are ≈ 4× the dark half's (G⁻¹′ ∝
// I^1.2), and the threshold's constant offset (7) is then a larger share of the dark half's
// median gradient, so the dark half gets fewer pixels. Weighted by G′(E), the tests read the
// raw gradients, alike on both halves: the selection splits evenly up to the texture's
// realisation and the random directions (DSO's gammaWeightsPixelSelect).
TEST(PixelSelector, TheResponsesSlopeSelectsAsInTheCamerasEncoding) {
  InverseResponse gamma;
  for (int k = 0; k < kResponseSize; ++k) gamma[k] = 255.0 * std::pow(k / 255.0, 2.2);
  const PhotometricCalibration calib(gamma, ImageF());
  const int w = 256, h = 128;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> texture(-25.0, 25.0);
  std::vector<double> blocks((w / 3 + 1) * (h / 3 + 1));
  for (double& b : blocks) b = texture(rng);
  ImageF corrected(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const double raw = (u < w / 2 ? 60.0 : 180.0) + blocks[(v / 3) * (w / 3 + 1) + u / 3];
      corrected(u, v) = static_cast<float>(calib.inverseResponse(raw));
    }
  const ImagePyramid pyramid(corrected, 3);
  PixelSelectorOptions options;
  options.desired_points = 600;
  auto darkShare = [&](const PixelSelectorOptions& o) {
    const std::vector<SelectedPixel> selected = selectPixels(pyramid, Mask(), o);
    EXPECT_GT(selected.size(), 400u);
    double dark = 0;
    for (const SelectedPixel& p : selected) dark += p.pixel.x() < w / 2;
    return dark / static_cast<double>(selected.size());
  };
  const double linear = darkShare(options);
  const auto slope = calib.responseSlopeTable();
  options.encoding =
      std::make_shared<CameraEncoding>(std::vector<float>(slope.begin(), slope.end()), ImageF());
  EXPECT_EQ(darkShare(options), linear);  // off by default: the table alone changes nothing
  options.camera_encoding = true;  // the setting `selection.camera_encoding=true`
  const double encoded = darkShare(options);
  std::cout << "dark half's share: linear " << linear << ", camera's encoding " << encoded << "\n";
  EXPECT_NEAR(encoded, 0.5, 0.1);
  EXPECT_LT(linear, encoded - 0.1);
}


// The vignette's part of the camera's encoding, ‖∇I‖ ≈ G′(V E) V ‖∇E‖ with G the identity: the
// same corrected texture behind a vignette of 0.25 on the left and 1 on the right reached the
// sensor at a quarter of the contrast on the left, so fewer pixels are selected there than
// on ∇E alone, where the halves are alike; a vignette of another size is refused.
TEST(PixelSelector, TheVignettesAttenuationCountsInTheCamerasEncoding) {
  const int w = 256, h = 128;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> texture(60.0, 140.0);
  std::vector<double> blocks((w / 3 + 1) * (h / 3 + 1));
  for (double& b : blocks) b = texture(rng);
  ImageF corrected(w, h), vignette(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      corrected(u, v) = static_cast<float>(blocks[(v / 3) * (w / 3 + 1) + (u % (w / 2)) / 3]);
      vignette(u, v) = u < w / 2 ? 0.25f : 1.f;
    }
  const ImagePyramid pyramid(corrected, 3);
  PixelSelectorOptions options;
  options.desired_points = 600;
  auto leftShare = [&](const PixelSelectorOptions& o) {
    const std::vector<SelectedPixel> selected = selectPixels(pyramid, Mask(), o);
    double left = 0;
    for (const SelectedPixel& p : selected) left += p.pixel.x() < w / 2;
    return left / static_cast<double>(selected.size());
  };
  const double plain = leftShare(options);
  options.encoding = std::make_shared<CameraEncoding>(std::vector<float>(), vignette);
  options.camera_encoding = true;
  const double encoded = leftShare(options);
  std::cout << "left half's share: on the corrected image " << plain << ", camera's encoding "
            << encoded << "\n";
  EXPECT_NEAR(plain, 0.5, 0.1);
  EXPECT_LT(encoded, plain - 0.1);
  options.encoding = std::make_shared<CameraEncoding>(std::vector<float>(), ImageF(w / 2, h, 1.f));
  EXPECT_THROW(selectPixels(pyramid, Mask(), options), Error);
}

}  // namespace
}  // namespace omnidso
