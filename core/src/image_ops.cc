#include "omnidso/core/image_ops.hpp"

namespace omnidso {

ImageF downsample2x2(const ImageF& image) {
  ImageF out(image.width() / 2, image.height() / 2);
  for (int v = 0; v < out.height(); ++v) {
    const float* top = image.row(2 * v);
    const float* bottom = image.row(2 * v + 1);
    float* dst = out.row(v);
    for (int u = 0; u < out.width(); ++u) {
      dst[u] = 0.25f * (top[2 * u] + top[2 * u + 1] + bottom[2 * u] + bottom[2 * u + 1]);
    }
  }
  return out;
}

Mask downsampleMask(const Mask& mask) {
  Mask out(mask.width() / 2, mask.height() / 2);
  for (int v = 0; v < out.height(); ++v) {
    const auto* top = mask.row(2 * v);
    const auto* bottom = mask.row(2 * v + 1);
    auto* dst = out.row(v);
    for (int u = 0; u < out.width(); ++u) {
      const bool all_valid = top[2 * u] && top[2 * u + 1] && bottom[2 * u] && bottom[2 * u + 1];
      dst[u] = all_valid ? 255 : 0;
    }
  }
  return out;
}

// Row by row with the borders peeled off, so the inner loops are branch-free and vectorise
// (before: a bounds test per pixel and axis, and dy read column-wise through a lambda). The
// arithmetic per pixel is the same — 0.5f·(next − previous) inside, next − previous at the
// borders — so the gradients are bit-identical.
ImageGradients computeGradients(const ImageF& image) {
  const int w = image.width();
  const int h = image.height();
  ImageGradients g{ImageF(w, h), ImageF(w, h)};  // zero: the derivative along a 1-pixel axis
  for (int v = 0; v < h; ++v) {
    const float* row = image.row(v);
    float* dx = g.dx.row(v);
    if (w >= 2) {
      dx[0] = row[1] - row[0];
      for (int u = 1; u < w - 1; ++u) dx[u] = 0.5f * (row[u + 1] - row[u - 1]);
      dx[w - 1] = row[w - 1] - row[w - 2];
    }
    if (h < 2) continue;
    float* dy = g.dy.row(v);
    if (v == 0 || v == h - 1) {  // one-sided: row 1 − row 0, row h−1 − row h−2
      const float* next = image.row(v == 0 ? 1 : h - 1);
      const float* previous = image.row(v == 0 ? 0 : h - 2);
      for (int u = 0; u < w; ++u) dy[u] = next[u] - previous[u];
    } else {
      const float* next = image.row(v + 1);
      const float* previous = image.row(v - 1);
      for (int u = 0; u < w; ++u) dy[u] = 0.5f * (next[u] - previous[u]);
    }
  }
  return g;
}

ImageF gradientMagnitudeSquared(const ImageGradients& gradients) {
  ImageF out(gradients.dx.width(), gradients.dx.height());
  const std::size_t n = out.size();
  const float* dx = gradients.dx.data();
  const float* dy = gradients.dy.data();
  float* dst = out.data();
  for (std::size_t i = 0; i < n; ++i) dst[i] = dx[i] * dx[i] + dy[i] * dy[i];
  return out;
}

}  // namespace omnidso
