#pragma once
// A frame's image preparation as it was before the session-13 speed-up (commit 684a0d0),
// kept as the oracle of the core tests (image_ops, pyramid, photometric calibration) and the
// "before" of benchmarks/image_preparation_bench.cc: every pixel through the general formula
// (a bounds test per pixel and axis; G⁻¹ interpolated per pixel). The fast code must give
// the same bits.
#include <algorithm>
#include <omnidso/core/image_ops.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <vector>

namespace omnidso::reference {

// Central difference along an axis of n samples, one-sided at the ends, 0 when n < 2.
template <typename Reader>
float difference(int i, int n, const Reader& at) {
  if (n < 2) return 0.0f;
  if (i == 0) return at(1) - at(0);
  if (i == n - 1) return at(n - 1) - at(n - 2);
  return 0.5f * (at(i + 1) - at(i - 1));
}

inline ImageGradients computeGradients(const ImageF& image) {
  const int w = image.width();
  const int h = image.height();
  ImageGradients g{ImageF(w, h), ImageF(w, h)};
  for (int v = 0; v < h; ++v) {
    const float* row = image.row(v);
    for (int u = 0; u < w; ++u) {
      g.dx(u, v) = difference(u, w, [row](int i) { return row[i]; });
      g.dy(u, v) = difference(v, h, [&image, u](int i) { return image(u, i); });
    }
  }
  return g;
}

// The levels and gradients ImagePyramid(level0, num_levels) holds (the levels by the
// library's downsample2x2, which the speed-up left as it was; image_ops_test checks it).
struct Pyramid {
  std::vector<ImageF> levels;
  std::vector<ImageGradients> gradients;
  Pyramid(const ImageF& level0, int num_levels) {
    levels.push_back(level0);
    for (int l = 1; l < num_levels; ++l) levels.push_back(omnidso::downsample2x2(levels.back()));
    for (const ImageF& level : levels) gradients.push_back(reference::computeGradients(level));
  }
};

inline ImageF correct(const PhotometricCalibration& calibration, const RawImage& raw) {
  const double to_table = raw.bit_depth == 16 ? 1.0 / 257.0 : 1.0;
  ImageF energy(raw.pixels.width(), raw.pixels.height());
  for (std::size_t i = 0; i < energy.size(); ++i) {
    double e = calibration.inverseResponse(raw.pixels.data()[i] * to_table);
    if (calibration.hasVignette()) {
      const double v = calibration.vignette().data()[i];
      e = v > 0.0 ? e / v : 0.0;
    }
    energy.data()[i] = static_cast<float>(e);
  }
  return energy;
}

}  // namespace omnidso::reference
