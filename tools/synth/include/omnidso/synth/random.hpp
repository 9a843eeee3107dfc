#pragma once
// Reproducible randomness for the renderer. Everything is derived from explicit seeds
// with integer arithmetic only, so that the bytes of a rendered dataset are the same on
// every platform and standard library (std::uniform_real_distribution and
// std::normal_distribution are implementation-defined, so they are not used).
//
// - hashCombine / counterHash: the SplitMix64 finaliser (Steele, Lea, Flood 2014) applied
//   to a running combination: a counter-based generator, used where the value must not
//   depend on evaluation order (per-pixel noise keyed by (seed, frame, pixel), so that
//   the image is independent of the thread count; texture lattice values keyed by
//   (seed, octave, cell)).
// - SeededRandom: std::mt19937_64 (fully specified by the standard) with uniforms made
//   from its 53 high bits and Gaussians by the Box–Muller transform
//   n = √(−2 ln u₁) cos(2π u₂), u₁ ∈ (0, 1].

#include <cmath>
#include <cstdint>
#include <random>

namespace omnidso::synth {

inline std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

inline std::uint64_t counterHash(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0) {
  return splitMix64(splitMix64(splitMix64(a) ^ b) ^ c);
}

// A uniform number in [0, 1) from the 53 high bits of a 64-bit word.
inline double unitFromBits(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * (1.0 / 9007199254740992.0);
}

// One standard-normal sample from one 64-bit hash (Box–Muller on its two 32-bit halves;
// u₁ ∈ (0, 1] keeps the logarithm finite). 32 bits per uniform limit the tails to
// |n| ≤ √(2 ln 2³²) ≈ 6.7σ, irrelevant for sensor noise.
inline double gaussianFromBits(std::uint64_t bits) {
  const double u1 = (static_cast<double>(bits >> 32) + 1.0) * (1.0 / 4294967296.0);
  const double u2 = static_cast<double>(bits & 0xFFFFFFFFULL) * (1.0 / 4294967296.0);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

class SeededRandom {
 public:
  explicit SeededRandom(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return unitFromBits(engine_()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int uniformInt(int lo, int hi_inclusive) {
    return lo + static_cast<int>(uniform() * (hi_inclusive - lo + 1));
  }
  double gaussian() { return gaussianFromBits(engine_()); }
  std::uint64_t bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

}  // namespace omnidso::synth
