#include <algorithm>
#include <deque>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {

Mask detectContentMask(const std::vector<const ImageU16*>& frames, int black_level,
                       double max_outside_fraction) {
  if (frames.empty()) throw Error("detectContentMask: no frames");
  const int w = frames.front()->width(), h = frames.front()->height();
  // Brightest value of every pixel over the frames.
  Image<std::uint16_t> brightest(w, h);
  std::fill(brightest.data(), brightest.data() + brightest.size(), 0);
  for (const ImageU16* f : frames) {
    if (f->width() != w || f->height() != h) throw Error("detectContentMask: frames differ in size");
    for (size_t i = 0; i < f->size(); ++i)
      brightest.data()[i] = std::max(brightest.data()[i], f->data()[i]);
  }
  Mask content(w, h);
  std::fill(content.data(), content.data() + content.size(), std::uint8_t{1});
  // Flood fill from every black border pixel through black pixels.
  std::deque<std::pair<int, int>> queue;
  auto seed = [&](int u, int v) {
    if (content(u, v) && brightest(u, v) <= black_level) {
      content(u, v) = 0;
      queue.emplace_back(u, v);
    }
  };
  for (int u = 0; u < w; ++u) {
    seed(u, 0);
    seed(u, h - 1);
  }
  for (int v = 0; v < h; ++v) {
    seed(0, v);
    seed(w - 1, v);
  }
  size_t outside = queue.size();
  while (!queue.empty()) {
    const auto [u, v] = queue.front();
    queue.pop_front();
    const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int x = u + du[k], y = v + dv[k];
      if (x < 0 || y < 0 || x >= w || y >= h) continue;
      const size_t before = queue.size();
      seed(x, y);
      outside += queue.size() - before;
    }
  }
  if (static_cast<double>(outside) > max_outside_fraction * static_cast<double>(content.size()))
    std::fill(content.data(), content.data() + content.size(), std::uint8_t{1});
  return content;
}

Mask erodeContent(const Mask& content, int radius) {
  const int w = content.width(), h = content.height();
  if (radius <= 0) return content;
  // Separable: a pixel survives when no non-content pixel lies within ±radius along rows,
  // then along columns (the Chebyshev ball).
  Mask rows(w, h), out(w, h);
  for (int v = 0; v < h; ++v) {
    int last_hole = -1000000;  // column of the last non-content pixel seen from the left
    std::vector<int> next_hole(static_cast<size_t>(w), 1000000);
    int next = 1000000;
    for (int u = w - 1; u >= 0; --u) {
      if (!content(u, v)) next = u;
      next_hole[static_cast<size_t>(u)] = next;
    }
    for (int u = 0; u < w; ++u) {
      if (!content(u, v)) last_hole = u;
      rows(u, v) = (u - last_hole > radius && next_hole[static_cast<size_t>(u)] - u > radius) ? 1 : 0;
    }
  }
  for (int u = 0; u < w; ++u) {
    int last_hole = -1000000;
    std::vector<int> next_hole(static_cast<size_t>(h), 1000000);
    int next = 1000000;
    for (int v = h - 1; v >= 0; --v) {
      if (!rows(u, v)) next = v;
      next_hole[static_cast<size_t>(v)] = next;
    }
    for (int v = 0; v < h; ++v) {
      if (!rows(u, v)) last_hole = v;
      out(u, v) = (v - last_hole > radius && next_hole[static_cast<size_t>(v)] - v > radius) ? 1 : 0;
    }
  }
  return out;
}

}  // namespace omnidso
