#include <algorithm>
#include <cmath>
#include <cstring>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <random>

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

// Per pixel: whether the 2r + 1 pixels centred on it along its row (`along_rows`) or its
// column are all valid — from the length of the valid run ending r pixels further on, so each
// pixel is read once instead of 2r + 1 times.
Mask centredRunsValid(const Mask& mask, int r, bool along_rows) {
  const int w = mask.width(), h = mask.height(), need = 2 * r + 1;
  Mask out(w, h, 0);
  if (along_rows) {
    for (int v = 0; v < h; ++v) {
      const std::uint8_t* in = mask.row(v);
      std::uint8_t* dst = out.row(v);
      int run = 0;
      for (int u = 0; u < w; ++u) {
        run = in[u] ? run + 1 : 0;
        if (run >= need) dst[u - r] = 1;
      }
    }
  } else {
    std::vector<int> run(w, 0);
    for (int v = 0; v < h; ++v) {
      const std::uint8_t* in = mask.row(v);
      for (int u = 0; u < w; ++u) run[u] = in[u] ? run[u] + 1 : 0;
      if (v - r < 0) continue;
      std::uint8_t* dst = out.row(v - r);
      for (int u = 0; u < w; ++u) dst[u] = run[u] >= need;
    }
  }
  return out;
}

// Where a pattern of radius `radius` fits: inside the image border, and — with a mask — the
// centre and the whole outline of the (2r+1)² square around it are valid (the outline, not
// the square's inside: that is the rule selection has always used, and for a convex mask such
// as a fisheye's image circle the two agree). The outline's four sides are the centred runs
// of the columns u ± r and the rows v ± r. 255 = usable.
Mask usableMask(const Mask& mask, int width, int height, int radius) {
  Mask out(width, height, 0);
  if (mask.empty()) {
    for (int v = radius; v < height - radius; ++v)
      std::fill(out.row(v) + radius, out.row(v) + std::max(radius, width - radius), 255);
    return out;
  }
  const Mask rows = centredRunsValid(mask, radius, true);
  const Mask cols = centredRunsValid(mask, radius, false);
  for (int v = radius; v < height - radius; ++v) {
    const std::uint8_t* centre = mask.row(v);
    const std::uint8_t* col = cols.row(v);
    const std::uint8_t* top = rows.row(v - radius);
    const std::uint8_t* bottom = rows.row(v + radius);
    std::uint8_t* dst = out.row(v);
    for (int u = radius; u < width - radius; ++u)
      dst[u] = (centre[u] && col[u - radius] && col[u + radius] && top[u] && bottom[u]) ? 255 : 0;
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

// The k-th smallest of `values` (0-based): the value std::nth_element puts at position k.
// Gradient norms are non-negative floats, whose order is that of their bit patterns read as
// unsigned integers, so the value is found by a radix select on those patterns, 8 bits at a
// time from the top: each pass counts the candidates' next byte, keeps those whose byte holds
// rank k and so fixes that byte of the answer — counting only, no comparisons to mispredict,
// and the candidates shrink fast (the medians took a quarter of a selection with
// nth_element). The answer is the bit pattern of the k-th smallest, so the same float bits.
// A NaN or negative value (−0 included: its pattern sorts last but it equals +0) is outside
// that order and goes to std::nth_element.
float kthSmallest(std::vector<float>& values, size_t k, std::vector<std::uint32_t>& keys) {
  keys.resize(values.size());
  std::memcpy(keys.data(), values.data(), values.size() * sizeof(float));
  bool ordered = true;
  for (std::uint32_t key : keys) ordered &= key <= 0x7f800000u;  // +0 .. +∞
  if (!ordered) {
    std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
    return values[k];
  }
  // The top byte over all keys, counted into 4 histograms in turn: the keys share few top
  // bytes (the exponent), and one histogram would make each count wait for the previous.
  std::uint32_t count[4][256] = {};
  const size_t n = keys.size();
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (int j = 0; j < 4; ++j) ++count[j][keys[i + j] >> 24];
  for (; i < n; ++i) ++count[0][keys[i] >> 24];
  for (int b = 0; b < 256; ++b) count[0][b] += count[1][b] + count[2][b] + count[3][b];
  std::uint32_t answer = 0;
  for (int shift = 24;; shift -= 8) {
    unsigned byte = 0;
    while (k >= count[0][byte]) k -= count[0][byte++];
    answer |= static_cast<std::uint32_t>(byte) << shift;
    if (shift == 0) break;
    // Keep the candidates whose byte is `byte` (their higher bytes agree already), without a
    // branch (whether a key matches is a coin toss to the predictor), then count their next byte.
    size_t kept = 0;
    for (std::uint32_t key : keys) {
      keys[kept] = key;
      kept += ((key >> shift) & 0xffu) == byte;
    }
    keys.resize(kept);
    std::fill(count[0], count[0] + 256, 0u);
    for (std::uint32_t key : keys) ++count[0][(key >> (shift - 8)) & 0xffu];
  }
  float out;
  std::memcpy(&out, &answer, sizeof(out));
  return out;
}

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
      raw(bx, by) = kthSmallest(values, values.size() / 2, keys);
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
  const Mask usable = usableMask(mask, image.width(), image.height(), options.border);
  long valid = 0;
  for (size_t i = 0; i < usable.size(); ++i) valid += usable.data()[i] != 0;
  if (valid == 0) return {};
  std::vector<Image<float>> norms;
  for (int level = 0; level < std::min(3, pyramid.numLevels()); ++level)
    norms.push_back(gradientNormImage(pyramid.gradients(level)));
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
