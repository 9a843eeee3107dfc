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

namespace {

// One pass of the separable erosion along lines of `length` pixels: out[i] = 1 when no zero
// of `in` lies within ±radius of i on its line. at(line, i) gives the pixel's index.
template <typename Index>
void erodeLines(const Mask& in, Mask& out, int lines, int length, int radius, Index at) {
  std::vector<int> next_hole(static_cast<size_t>(length));
  for (int line = 0; line < lines; ++line) {
    int next = 1 << 30;
    for (int i = length - 1; i >= 0; --i) {
      if (!in.data()[at(line, i)]) next = i;
      next_hole[static_cast<size_t>(i)] = next;
    }
    int last_hole = -(1 << 30);
    for (int i = 0; i < length; ++i) {
      if (!in.data()[at(line, i)]) last_hole = i;
      out.data()[at(line, i)] =
          (i - last_hole > radius && next_hole[static_cast<size_t>(i)] - i > radius) ? 1 : 0;
    }
  }
}

}  // namespace

Mask erodeContent(const Mask& content, int radius) {
  if (radius <= 0) return content;
  const int w = content.width(), h = content.height();
  // Erosion by the (2r+1)² square = along rows, then along columns.
  Mask rows(w, h), out(w, h);
  erodeLines(content, rows, h, w, radius,
             [w](int v, int u) { return static_cast<size_t>(v) * w + u; });
  erodeLines(rows, out, w, h, radius,
             [w](int u, int v) { return static_cast<size_t>(v) * w + u; });
  return out;
}

std::vector<Mask> contentPyramid(const Mask& level0, int num_levels) {
  if (num_levels < 1) throw Error("contentPyramid: number of levels must be at least 1");
  std::vector<Mask> levels = {level0};
  levels.reserve(static_cast<size_t>(num_levels));
  for (int l = 1; l < num_levels; ++l) {
    const Mask& fine = levels.back();
    Mask coarse(fine.width() / 2, fine.height() / 2);
    for (int v = 0; v < coarse.height(); ++v)
      for (int u = 0; u < coarse.width(); ++u)
        coarse(u, v) = fine(2 * u, 2 * v) && fine(2 * u + 1, 2 * v) && fine(2 * u, 2 * v + 1) &&
                       fine(2 * u + 1, 2 * v + 1);
    levels.push_back(std::move(coarse));
  }
  return levels;
}

ContentExtent contentExtent(const Mask& content) {
  int u0 = content.width(), u1 = -1, v0 = content.height(), v1 = -1;
  for (int v = 0; v < content.height(); ++v)
    for (int u = 0; u < content.width(); ++u)
      if (content(u, v)) {
        u0 = std::min(u0, u);
        u1 = std::max(u1, u);
        v0 = std::min(v0, v);
        v1 = std::max(v1, v);
      }
  if (u1 < 0) return {};
  return {u1 - u0 + 1, v1 - v0 + 1};
}

}  // namespace omnidso
