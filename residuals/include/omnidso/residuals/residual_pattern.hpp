#pragma once
// Residual patterns: the pixel offsets around a host pixel whose intensities form one
// photometric residual block (paper eq. 5, the neighbourhood N_p). Selected at compile time
// by the pattern size, because the residual kernels are SizedCostFunctions of that size:
//   1: the host pixel alone;
//   5: a cross of radius 1 (the pixel and its 4 neighbours);
//   8: DSO's pattern, a sparse diamond of radius 2 (Engel et al., "Direct Sparse Odometry",
//      Fig. 4: offsets (0,−2) (−1,−1) (1,−1) (−2,0) (0,0) (2,0) (−1,1) (0,2)).
// Offsets are (du, dv) in pixels of the pyramid level the residual is evaluated on.

#include <array>

namespace omnidso {

struct PatternOffset {
  int du;
  int dv;
};

template <int kSize>
struct ResidualPattern;

template <>
struct ResidualPattern<1> {
  static constexpr const char* kName = "single";
  static constexpr std::array<PatternOffset, 1> kOffsets = {{{0, 0}}};
};

template <>
struct ResidualPattern<5> {
  static constexpr const char* kName = "cross5";
  static constexpr std::array<PatternOffset, 5> kOffsets = {
      {{0, -1}, {-1, 0}, {0, 0}, {1, 0}, {0, 1}}};
};

template <>
struct ResidualPattern<8> {
  static constexpr const char* kName = "dso8";
  static constexpr std::array<PatternOffset, 8> kOffsets = {
      {{0, -2}, {-1, -1}, {1, -1}, {-2, 0}, {0, 0}, {2, 0}, {-1, 1}, {0, 2}}};
};

// Offset o of the pattern laid out on steps of `spread` pixels. Spread 1 is the pattern as
// defined; on an image magnified k× from its source (a pinhole crop of a fisheye) spread k puts
// the pattern's pixels on the source's pixels, so that they carry independent noise and texture
// (docs/performance.md, "The narrow view without resampling").
template <int kSize>
constexpr PatternOffset spreadOffset(int o, int spread) {
  return {ResidualPattern<kSize>::kOffsets[o].du * spread,
          ResidualPattern<kSize>::kOffsets[o].dv * spread};
}

// Largest |du| or |dv| of a pattern: the margin a host pixel needs from the image border.
template <int kSize>
constexpr int patternRadius() {
  int radius = 0;
  for (const PatternOffset& o : ResidualPattern<kSize>::kOffsets) {
    radius = o.du > radius ? o.du : radius;
    radius = -o.du > radius ? -o.du : radius;
    radius = o.dv > radius ? o.dv : radius;
    radius = -o.dv > radius ? -o.dv : radius;
  }
  return radius;
}

}  // namespace omnidso
