#include <array>
#include <omnidso/frontend/reference_dilation.hpp>

namespace omnidso {

LevelInverseDistances dilateInverseDistances(const LevelInverseDistances& points, int width,
                                             int height, DilationNeighbours neighbours,
                                             const Mask* content) {
  const bool diagonal = neighbours == DilationNeighbours::kDiagonal;
  // Offsets (du, dv) of the four neighbours; symmetric, so a point's neighbours are the pixels
  // that have the point among theirs.
  const std::array<std::pair<int, int>, 4> offsets =
      diagonal ? std::array<std::pair<int, int>, 4>{{{1, 1}, {-1, -1}, {1, -1}, {-1, 1}}}
               : std::array<std::pair<int, int>, 4>{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};
  std::map<std::pair<int, int>, std::pair<double, int>> sums;  // (v, u) → (Σ d, count)
  for (const auto& [key, d] : points)
    for (const auto& [du, dv] : offsets) {
      const int v = key.first + dv, u = key.second + du;
      if (u < 1 || v < 1 || u >= width - 1 || v >= height - 1) continue;
      if (points.count({v, u})) continue;
      if (content && !(*content)(u, v)) continue;
      auto& sum = sums[{v, u}];
      sum.first += d;
      ++sum.second;
    }
  LevelInverseDistances out = points;
  for (const auto& [key, sum] : sums) out[key] = sum.first / sum.second;
  return out;
}

}  // namespace omnidso
