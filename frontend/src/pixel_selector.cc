#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <random>

#include "pixel_selector_detail.hpp"

namespace omnidso {
namespace {

// ‖∇I‖ of a whole level, computed once per selection (the threshold map, the level tests and
// the selected pixels' gradients read it).
Image<float> gradientNormImage(const ImageGradients& g) {
  Image<float> out(g.dx.width(), g.dx.height());
  const float* dx = g.dx.data();
  const float* dy = g.dy.data();
  float* dst = out.data();
  for (size_t i = 0; i < out.size(); ++i) dst[i] = std::sqrt(dx[i] * dx[i] + dy[i] * dy[i]);
  return out;
}

// ‖∇E‖ → ‖∇I‖ ≈ G′(V E) V ‖∇E‖ (PixelSelectorOptions::encoding).
void weightByEncoding(const ImageF& intensity, int level, const PixelSelectorOptions& options,
                      Image<float>* norm) {
  if (!options.encoding || options.encoding->linear()) return;
  const ImageF slope = options.encoding->slope(intensity, level);
  float* n = norm->data();
  const float* s = slope.data();
  for (size_t i = 0; i < norm->size(); ++i) n[i] *= s[i];
}

struct Candidate {
  int u = -1, v = -1;
  float score = -1.f;
  bool valid() const { return u >= 0; }
};

class Selector {
 public:
  // norms: ‖∇I‖ of levels 0, 1, 2 (as many as the pyramid has). What a pixel offers on each
  // level — whether it is usable and passes that level's threshold — does not depend on d, so
  // it is tabulated once as one byte per level-0 pixel (bit L: level L); every adaptation
  // round then scores only the pixels that pass, reading the level's own gradient images.
  // (Before: a pass mask and dx, dy copies per level at level-0 resolution, 6 MB zeroed and
  // written per selection, a quarter of its time.)
  Selector(const ImagePyramid& pyramid, const std::vector<Image<float>>& norms,
           const Mask& usable, const Image<float>& thresholds, const PixelSelectorOptions& options)
      : norms_(norms),
        options_(options),
        flags_(usable.width(), usable.height(), 0),
        levels_(static_cast<int>(norms.size())) {
    const int w = usable.width(), h = usable.height(), bs = options.threshold_block_size;
    const int levels = static_cast<int>(norms.size());
    // Per column: its threshold block and, per level, the level-L column covering it.
    std::vector<int> block_u(w);
    for (int u = 0; u < w; ++u) block_u[u] = std::min(u / bs, thresholds.width() - 1);
    float factor[3];
    double f = 1.0;
    for (int level = 0; level < levels; ++level) {
      const ImageGradients& g = pyramid.gradients(level);
      gradients_[level] = &g;
      factor[level] = static_cast<float>(f);
      f *= options.coarser_level_factor;
      columns_[level].resize(w);
      rows_[level].resize(h);
      for (int u = 0; u < w; ++u) columns_[level][u] = std::min(u >> level, g.dx.width() - 1);
      for (int v = 0; v < h; ++v) rows_[level][v] = std::min(v >> level, g.dx.height() - 1);
    }
    for (int v = 0; v < h; ++v) {
      const float* threshold_row = thresholds.row(std::min(v / bs, thresholds.height() - 1));
      const float* norm_row[3];
      for (int level = 0; level < levels; ++level)
        norm_row[level] = norms[level].row(rows_[level][v]);
      const std::uint8_t* use = usable.row(v);
      std::uint8_t* dst = flags_.row(v);
      for (int u = 0; u < w; ++u) {
        if (!use[u]) continue;
        std::uint8_t bits = 0;
        for (int level = 0; level < levels; ++level) {
          const float threshold = factor[level] * threshold_row[block_u[u]];
          // "not ≤" rather than ">": the rule the tables always used (NaN passes, and then
          // never wins a comparison of scores).
          if (!(norm_row[level][columns_[level][u]] <= threshold))
            bits |= static_cast<std::uint8_t>(1u << level);
        }
        dst[u] = bits;
      }
    }
  }

  std::vector<SelectedPixel> run(int d) const {
    std::vector<SelectedPixel> out;
    std::mt19937_64 rng(options_.seed);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    const int w = flags_.width(), h = flags_.height();
    for (int v4 = 0; v4 < h; v4 += 4 * d)
      for (int u4 = 0; u4 < w; u4 += 4 * d) {
        bool any4 = false;
        Candidate best4;
        for (int v2 = v4; v2 < std::min(v4 + 4 * d, h); v2 += 2 * d)
          for (int u2 = u4; u2 < std::min(u4 + 4 * d, w); u2 += 2 * d) {
            bool any2 = false;
            Candidate best2;
            for (int v1 = v2; v1 < std::min(v2 + 2 * d, h); v1 += d)
              for (int u1 = u2; u1 < std::min(u2 + 2 * d, w); u1 += d) {
                const double a = angle(rng);
                const Eigen::Vector2f dir(std::cos(a), std::sin(a));
                Candidate best1;
                const int u_end = std::min(u1 + d, w);
                for (int v = v1; v < std::min(v1 + d, h); ++v) {
                  const std::uint8_t* bits = flags_.row(v);
                  Rows r[3];
                  for (int level = 0; level < levels_; ++level) r[level] = rows(level, v);
                  for (int u = u1; u < u_end; ++u) {
                    const unsigned b = bits[u];
                    if (!b) continue;
                    if (b & 1) consider(r[0], u, u, v, dir, &best1);
                    if (b & 2) consider(r[1], columns_[1][u], u, v, dir, &best2);
                    if (b & 4) consider(r[2], columns_[2][u], u, v, dir, &best4);
                  }
                }
                if (best1.valid()) {
                  out.push_back(make(best1, 0));
                  any2 = any4 = true;
                }
              }
            if (!any2 && best2.valid()) {
              out.push_back(make(best2, 1));
              any4 = true;
            }
          }
        if (!any4 && best4.valid()) out.push_back(make(best4, 2));
      }
    return out;
  }

 private:
  // The gradient rows of a level that cover level-0 row v.
  struct Rows {
    const float* dx = nullptr;
    const float* dy = nullptr;
  };
  Rows rows(int level, int v) const {
    const int vl = rows_[level][v];
    return {gradients_[level]->dx.row(vl), gradients_[level]->dy.row(vl)};
  }

  // Scores the level's gradient at column ul of its row r for level-0 pixel (u, v).
  static void consider(const Rows& r, int ul, int u, int v, const Eigen::Vector2f& dir,
                       Candidate* best) {
    const float score = std::abs(r.dx[ul] * dir.x() + r.dy[ul] * dir.y());
    if (score > best->score) *best = {u, v, score};
  }

  SelectedPixel make(const Candidate& c, int level) const {
    SelectedPixel p;
    p.pixel = Eigen::Vector2i(c.u, c.v);
    p.level = level;
    p.gradient = norms_[0](c.u, c.v);
    return p;
  }

  const std::vector<Image<float>>& norms_;
  const PixelSelectorOptions& options_;
  Mask flags_;
  int levels_;
  const ImageGradients* gradients_[3] = {nullptr, nullptr, nullptr};
  std::vector<int> columns_[3], rows_[3];
};

}  // namespace

Image<float> gradientThresholdMap(const Image<float>& gradient_norm, const Mask& mask,
                                  int block_size, double offset) {
  const int w = gradient_norm.width(), h = gradient_norm.height();
  const int bw = (w + block_size - 1) / block_size, bh = (h + block_size - 1) / block_size;
  Image<float> raw(bw, bh, 0.f);
  Image<std::uint8_t> has(bw, bh, 0);
  std::vector<float> values;
  std::vector<std::uint32_t> keys;
  values.reserve(static_cast<size_t>(block_size) * block_size);
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      values.clear();
      const int u0 = bx * block_size, u1 = std::min(u0 + block_size, w);
      for (int v = by * block_size; v < std::min((by + 1) * block_size, h); ++v) {
        const float* norm = gradient_norm.row(v);
        if (mask.empty()) {
          values.insert(values.end(), norm + u0, norm + u1);
          continue;
        }
        const std::uint8_t* valid = mask.row(v);
        for (int u = u0; u < u1; ++u)
          if (valid[u]) values.push_back(norm[u]);
      }
      if (values.empty()) continue;
      raw(bx, by) = detail::kthSmallest(values, values.size() / 2, keys);
      has(bx, by) = 1;
    }
  // Smooth over the 3×3 neighbourhood of blocks that have valid pixels.
  Image<float> out(bw, bh, static_cast<float>(offset));
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      double sum = 0.0;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = bx + dx, y = by + dy;
          if (x < 0 || y < 0 || x >= bw || y >= bh || !has(x, y)) continue;
          sum += raw(x, y);
          ++n;
        }
      out(bx, by) = static_cast<float>((n ? sum / n : 0.0) + offset);
    }
  return out;
}

std::vector<SelectedPixel> selectPixels(const ImagePyramid& pyramid, const Mask& mask,
                                        const PixelSelectorOptions& options) {
  const ImageF& image = pyramid.level(0);
  if (!mask.empty() && (mask.width() != image.width() || mask.height() != image.height()))
    throw Error("selectPixels: the validity mask is " + std::to_string(mask.width()) + "x" +
                std::to_string(mask.height()) + ", the image " + std::to_string(image.width()) +
                "x" + std::to_string(image.height()));
  if (options.desired_points <= 0) return {};
  if (options.border < 0 || options.threshold_block_size < 1)
    throw Error("selectPixels: border must be >= 0 and threshold_block_size >= 1");
  const Mask usable = detail::usableMask(mask, image.width(), image.height(), options.border);
  long valid = 0;
  for (size_t i = 0; i < usable.size(); ++i) valid += usable.data()[i] != 0;
  if (valid == 0) return {};
  std::vector<Image<float>> norms;
  for (int level = 0; level < std::min(3, pyramid.numLevels()); ++level) {
    norms.push_back(gradientNormImage(pyramid.gradients(level)));
    if (options.camera_encoding) weightByEncoding(pyramid.level(level), level, options, &norms.back());
  }
  const Image<float> thresholds = gradientThresholdMap(
      norms[0], mask, options.threshold_block_size, options.gradient_threshold_offset);
  const Selector selector(pyramid, norms, usable, thresholds, options);
  double d = std::max(1.0, std::sqrt(static_cast<double>(valid) / options.desired_points));
  std::vector<SelectedPixel> best = selector.run(static_cast<int>(std::lround(d)));
  for (int round = 0; round < options.max_adaptation_rounds; ++round) {
    const double ratio = static_cast<double>(best.size()) / options.desired_points;
    if (ratio > 0.8 && ratio < 1.2) break;
    if (best.empty()) {
      d = std::max(1.0, d / 2.0);
    } else {
      d = std::max(1.0, d * std::sqrt(ratio));
    }
    std::vector<SelectedPixel> next = selector.run(static_cast<int>(std::lround(d)));
    const double next_ratio = static_cast<double>(next.size()) / options.desired_points;
    if (std::abs(std::log(std::max(next_ratio, 1e-9))) <
        std::abs(std::log(std::max(ratio, 1e-9))))
      best = std::move(next);
    if (d <= 1.0) break;
  }
  return best;
}

}  // namespace omnidso
