// Two steps of candidate selection (pixel_selector_detail.hpp) that have their own tricks:
// the usable mask from run lengths and the block medians by a radix select.
#include "pixel_selector_detail.hpp"

#include <algorithm>
#include <cstring>

namespace omnidso::detail {

// Per pixel: whether the 2r + 1 pixels centred on it along its row (`along_rows`) or its
// column are all valid — from the length of the valid run ending r pixels further on, so each
// pixel is read once instead of 2r + 1 times.
static Mask centredRunsValid(const Mask& mask, int r, bool along_rows) {
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

}  // namespace omnidso::detail
