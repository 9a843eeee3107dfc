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

namespace {

// Central difference of samples a[i−step], a[i+step] along one axis of length n, one-sided
// at the ends; `at(i)` reads sample i.
template <typename Reader>
float difference(int i, int n, const Reader& at) {
  if (n < 2) return 0.0f;
  if (i == 0) return at(1) - at(0);
  if (i == n - 1) return at(n - 1) - at(n - 2);
  return 0.5f * (at(i + 1) - at(i - 1));
}

}  // namespace

ImageGradients computeGradients(const ImageF& image) {
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
