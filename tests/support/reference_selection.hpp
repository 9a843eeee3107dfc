#pragma once
// The candidate selection as it was before the session-13 speed-up (commit 684a0d0), kept
// unchanged as the oracle of tests/frontend/pixel_selector_test.cc and the "before" of
// benchmarks/pixel_selection_bench.cc: straightforward (every table at level-0 resolution,
// the usable mask tested pixel by pixel), and what the fast code must reproduce bit for bit.
#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <random>
#include <string>
#include <vector>

namespace omnidso::reference {


// ‖∇I‖ of a whole level, computed once per selection (the threshold map and every
// adaptation round read it).
inline Image<float> gradientNormImage(const ImageGradients& g) {
  Image<float> out(g.dx.width(), g.dx.height());
  for (size_t i = 0; i < out.size(); ++i)
    out.data()[i] = std::sqrt(g.dx.data()[i] * g.dx.data()[i] + g.dy.data()[i] * g.dy.data()[i]);
  return out;
}

// The mask eroded by `radius` (and the image border): where a pattern fits entirely.
inline Mask usableMask(const Mask& mask, int width, int height, int radius) {
  Mask out(width, height, 0);
  for (int v = radius; v < height - radius; ++v)
    for (int u = radius; u < width - radius; ++u) {
      bool ok = true;
      if (!mask.empty())
        for (int dv = -radius; dv <= radius && ok; ++dv)
          ok = mask(u - radius, v + dv) && mask(u + radius, v + dv);
      if (ok && !mask.empty())
        for (int du = -radius; du <= radius && ok; ++du)
          ok = mask(u + du, v - radius) && mask(u + du, v + radius);
      if (ok && !mask.empty()) ok = mask(u, v);
      out(u, v) = ok ? 255 : 0;
    }
  return out;
}

struct Candidate {
  int u = -1, v = -1;
  float score = -1.f;
  bool valid() const { return u >= 0; }
};

class Selector {
 public:
  // norms: ‖∇I‖ of levels 0, 1, 2 (as many as the pyramid has). What a pixel offers on each
  // level — whether it passes that level's threshold, and the level's gradient there — does
  // not depend on d, so it is tabulated once at level-0 resolution; every adaptation round
  // then only scores the pixels that pass (the rounds took ¾ of a selection).
  Selector(const ImagePyramid& pyramid, const std::vector<Image<float>>& norms,
           const Mask& usable, const Image<float>& thresholds, const PixelSelectorOptions& options)
      : norms_(norms), usable_(usable), options_(options) {
    double factor = 1.0;
    for (int level = 0; level < static_cast<int>(norms.size()); ++level) {
      levels_.push_back(tabulate(level, pyramid.gradients(level), norms[level], thresholds,
                                 static_cast<float>(factor)));
      factor *= options.coarser_level_factor;
    }
  }

  std::vector<SelectedPixel> run(int d) {
    std::vector<SelectedPixel> out;
    std::mt19937_64 rng(options_.seed);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
    const int w = usable_.width(), h = usable_.height();
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
                for (int v = v1; v < std::min(v1 + d, h); ++v)
                  for (int u = u1; u < std::min(u1 + d, w); ++u) {
                    if (!usable_(u, v)) continue;
                    consider(0, u, v, dir, &best1);
                    consider(1, u, v, dir, &best2);
                    consider(2, u, v, dir, &best4);
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
  // Per level-0 pixel (u, v): whether the level-L pixel covering it passes factor_L × the
  // threshold of (u, v)'s block, and that level-L pixel's gradient.
  struct LevelTable {
    Mask passes;
    Image<float> dx, dy;
  };
  LevelTable tabulate(int level, const ImageGradients& g, const Image<float>& norm,
                      const Image<float>& thresholds, float factor) const {
    const int w = usable_.width(), h = usable_.height(), bs = options_.threshold_block_size;
    LevelTable t{Mask(w, h, 0), Image<float>(w, h, 0.f), Image<float>(w, h, 0.f)};
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const int ul = std::min(u >> level, g.dx.width() - 1);
        const int vl = std::min(v >> level, g.dx.height() - 1);
        const float threshold =
            factor * thresholds(std::min(u / bs, thresholds.width() - 1),
                                std::min(v / bs, thresholds.height() - 1));
        if (norm(ul, vl) <= threshold) continue;
        t.passes(u, v) = 1;
        t.dx(u, v) = g.dx(ul, vl);
        t.dy(u, v) = g.dy(ul, vl);
      }
    return t;
  }

  void consider(int level, int u, int v, const Eigen::Vector2f& dir, Candidate* best) const {
    if (level >= static_cast<int>(levels_.size())) return;
    const LevelTable& t = levels_[level];
    if (!t.passes(u, v)) return;
    const float score = std::abs(t.dx(u, v) * dir.x() + t.dy(u, v) * dir.y());
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
  const Mask& usable_;
  const PixelSelectorOptions& options_;
  std::vector<LevelTable> levels_;
};


inline Image<float> gradientThresholdMap(const Image<float>& gradient_norm, const Mask& mask,
                                  int block_size, double offset) {
  const int w = gradient_norm.width(), h = gradient_norm.height();
  const int bw = (w + block_size - 1) / block_size, bh = (h + block_size - 1) / block_size;
  Image<float> raw(bw, bh, 0.f);
  Image<std::uint8_t> has(bw, bh, 0);
  std::vector<float> values;
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      values.clear();
      for (int v = by * block_size; v < std::min((by + 1) * block_size, h); ++v)
        for (int u = bx * block_size; u < std::min((bx + 1) * block_size, w); ++u)
          if (mask.empty() || mask(u, v)) values.push_back(gradient_norm(u, v));
      if (values.empty()) continue;
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      raw(bx, by) = values[values.size() / 2];
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

inline std::vector<SelectedPixel> selectPixels(const ImagePyramid& pyramid, const Mask& mask,
                                        const PixelSelectorOptions& options) {
  const ImageF& image = pyramid.level(0);
  if (!mask.empty() && (mask.width() != image.width() || mask.height() != image.height()))
    throw Error("selectPixels: the validity mask is " + std::to_string(mask.width()) + "x" +
                std::to_string(mask.height()) + ", the image " + std::to_string(image.width()) +
                "x" + std::to_string(image.height()));
  if (options.desired_points <= 0) return {};
  const Mask usable = usableMask(mask, image.width(), image.height(), options.border);
  long valid = 0;
  for (size_t i = 0; i < usable.size(); ++i) valid += usable.data()[i] != 0;
  if (valid == 0) return {};
  std::vector<Image<float>> norms;
  for (int level = 0; level < std::min(3, pyramid.numLevels()); ++level)
    norms.push_back(gradientNormImage(pyramid.gradients(level)));
  const Image<float> thresholds = reference::gradientThresholdMap(
      norms[0], mask, options.threshold_block_size, options.gradient_threshold_offset);
  Selector selector(pyramid, norms, usable, thresholds, options);
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

}  // namespace omnidso::reference
