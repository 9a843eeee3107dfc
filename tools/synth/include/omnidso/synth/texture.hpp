#pragma once
// Surface textures of the synthetic scene: radiance images with texture coordinates in
// metres, so that every surface has the same resolution (texel_size metres per texel).
//
// Procedural textures imitate the statistics of real indoor images (paper Sec. VI): a
// base of multi-octave value noise with a 1/f amplitude spectrum (amplitude ∝ wavelength),
// "posters" (rectangles with sharp edges, their own contrast), thin lines, and nearly
// textureless patches (as in the paper's T5 sequences, where direct methods lose track).
// Radiance values lie in [kMinRadiance, 1].

#include <cstdint>
#include <string>

#include <omnidso/core/image.hpp>

namespace omnidso::synth {

inline constexpr float kMinRadiance = 0.03f;

class Texture {
 public:
  Texture() = default;
  // radiance: texel (i, j) covers [i, i+1)·texel_size × [j, j+1)·texel_size metres.
  Texture(const ImageF& radiance, double texel_size);

  // Bilinear radiance at texture coordinates (s, t) in metres from the texture's corner;
  // coordinates are clamped to the texture (surfaces are exactly the texture's size, so
  // clamping only acts on rounding at the edges).
  float sample(float s_m, float t_m) const {
    float x = s_m * inv_texel_ - 0.5f;
    float y = t_m * inv_texel_ - 0.5f;
    x = x < 0.f ? 0.f : (x > max_x_ ? max_x_ : x);
    y = y < 0.f ? 0.f : (y > max_y_ ? max_y_ : y);
    const int x0 = static_cast<int>(x);
    const int y0 = static_cast<int>(y);
    const float fx = x - static_cast<float>(x0);
    const float fy = y - static_cast<float>(y0);
    const float* r0 = radiance_.data() + static_cast<size_t>(y0) * stride_ + x0;
    const float* r1 = r0 + stride_;
    const float top = r0[0] + fx * (r0[1] - r0[0]);
    const float bottom = r1[0] + fx * (r1[1] - r1[0]);
    return top + fy * (bottom - top);
  }

  // The radiance image with its extra last column and row (copies of the edge).
  const ImageF& paddedRadiance() const { return radiance_; }
  double texelSize() const { return texel_size_; }

 private:
  ImageF radiance_;  // padded by one column and row so that sample() needs no bound test
  double texel_size_ = 0.01;
  float inv_texel_ = 100.f;
  float max_x_ = 0.f;
  float max_y_ = 0.f;
  int stride_ = 0;
};

// What a procedural texture contains; each count is a mean, the actual number is random.
struct TextureRecipe {
  float mean = 0.45f;           // mean radiance of the base
  float contrast = 0.25f;       // amplitude of the base noise (largest octave)
  double largest_wavelength_m = 1.0;
  int octaves = 6;              // wavelengths largest / 2^k, k < octaves
  double posters_per_m2 = 0.4;  // rectangles with sharp edges
  double lines_per_m2 = 0.3;    // thin dark or bright stripes
  double flat_patches_per_m2 = 0.0;  // nearly textureless rectangles (contrast ~1 %)
  double bright_patches_per_m2 = 0.0;  // lamps / windows, radiance near 1
};

// The radiance of a procedural texture of width_m × height_m metres (at least one texel
// each way); the same seed gives the same texels.
ImageF makeProceduralRadiance(double width_m, double height_m, double texel_size,
                              const TextureRecipe& recipe, std::uint64_t seed);

// Places an image file (read with core's image_io, grey level g → radiance
// max(g/255, kMinRadiance)) as a poster of poster_w_m × poster_h_m metres with its top-left
// corner at (s_m, t_m) (nearest texel of the image; parts outside are cut off). Throws
// omnidso::Error naming the file when it cannot be read.
void pasteImagePoster(ImageF& radiance, double texel_size, const std::string& image_path,
                      double s_m, double t_m, double poster_w_m, double poster_h_m);

}  // namespace omnidso::synth
