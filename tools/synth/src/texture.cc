// Procedural radiance textures (see texture.hpp for what they contain and why).
#include <omnidso/synth/texture.hpp>

#include <algorithm>
#include <cmath>

#include <omnidso/core/image_io.hpp>
#include <omnidso/synth/random.hpp>

namespace omnidso::synth {

Texture::Texture(const ImageF& radiance, double texel_size)
    : radiance_(radiance.width() + 1, radiance.height() + 1),
      texel_size_(texel_size),
      inv_texel_(static_cast<float>(1.0 / texel_size)),
      max_x_(static_cast<float>(radiance.width() - 1)),
      max_y_(static_cast<float>(radiance.height() - 1)),
      stride_(radiance.width() + 1) {
  for (int v = 0; v <= radiance.height(); ++v) {
    for (int u = 0; u <= radiance.width(); ++u) {
      radiance_(u, v) = radiance(std::min(u, radiance.width() - 1),
                                 std::min(v, radiance.height() - 1));
    }
  }
}

namespace {

// Adds Σ_k a_k·noise_k with wavelength λ/2^k and amplitude contrast·2^−k (a 1/f spectrum:
// amplitude proportional to wavelength) to the texels of the rectangle [u0,u1)×[v0,v1).
// Each octave is value noise: hashed lattice values in [−1, 1] at integer cells (one cell per
// wavelength), blended with the cubic smoothstep 3f² − 2f³ (C¹: no creases at cell borders).
// The lattice of the rectangle is hashed once per octave, then interpolated per texel.
void addFractalNoise(ImageF& image, double texel_size, int u0, int v0, int u1, int v1,
                     double largest_wavelength_m, int octaves, float contrast,
                     std::uint64_t key) {
  if (u1 <= u0 || v1 <= v0) return;
  for (int k = 0; k < octaves; ++k) {
    const double wavelength = largest_wavelength_m / static_cast<double>(1 << k);
    const float amplitude = contrast / static_cast<float>(1 << k);
    const double cells_per_texel = texel_size / wavelength;
    const std::uint64_t octave_key = counterHash(key, static_cast<std::uint64_t>(k));
    const int cell_u0 = static_cast<int>(std::floor((u0 + 0.5) * cells_per_texel));
    const int cell_v0 = static_cast<int>(std::floor((v0 + 0.5) * cells_per_texel));
    const int cells_u = static_cast<int>(std::floor((u1 - 0.5) * cells_per_texel)) - cell_u0 + 2;
    const int cells_v = static_cast<int>(std::floor((v1 - 0.5) * cells_per_texel)) - cell_v0 + 2;
    ImageF lattice(cells_u, cells_v);
    for (int j = 0; j < cells_v; ++j) {
      for (int i = 0; i < cells_u; ++i) {
        lattice(i, j) = static_cast<float>(
            2.0 * unitFromBits(counterHash(octave_key, static_cast<std::uint64_t>(cell_u0 + i),
                                           static_cast<std::uint64_t>(cell_v0 + j))) -
            1.0);
      }
    }
    for (int v = v0; v < v1; ++v) {
      const double y = (v + 0.5) * cells_per_texel;
      const int j = static_cast<int>(std::floor(y)) - cell_v0;
      const float fy = static_cast<float>(y - std::floor(y));
      const float sy = fy * fy * (3.f - 2.f * fy);
      float* row = image.row(v);
      for (int u = u0; u < u1; ++u) {
        const double x = (u + 0.5) * cells_per_texel;
        const int i = static_cast<int>(std::floor(x)) - cell_u0;
        const float fx = static_cast<float>(x - std::floor(x));
        const float sx = fx * fx * (3.f - 2.f * fx);
        const float top = lattice(i, j) + sx * (lattice(i + 1, j) - lattice(i, j));
        const float bottom = lattice(i, j + 1) + sx * (lattice(i + 1, j + 1) - lattice(i, j + 1));
        row[u] += amplitude * (top + sy * (bottom - top));
      }
    }
  }
}

struct TexelRect {
  int u0, v0, u1, v1;
};

// A random rectangle of the given size range (metres), clipped to the image.
TexelRect randomRect(SeededRandom& random, const ImageF& image, double texel_size,
                     double min_w, double max_w, double min_h, double max_h) {
  const int w = std::max(1, static_cast<int>(random.uniform(min_w, max_w) / texel_size));
  const int h = std::max(1, static_cast<int>(random.uniform(min_h, max_h) / texel_size));
  const int u0 = static_cast<int>(random.uniform(-0.2, 1.0) * image.width());
  const int v0 = static_cast<int>(random.uniform(-0.2, 1.0) * image.height());
  return {std::clamp(u0, 0, image.width()), std::clamp(v0, 0, image.height()),
          std::clamp(u0 + w, 0, image.width()), std::clamp(v0 + h, 0, image.height())};
}

void fillRect(ImageF& image, const TexelRect& r, float value) {
  for (int v = r.v0; v < r.v1; ++v) std::fill(image.row(v) + r.u0, image.row(v) + r.u1, value);
}

// A random count with the given mean: floor(mean · U(0.5, 1.5) + U(0, 1)).
int randomCount(SeededRandom& random, double mean) {
  return static_cast<int>(mean * random.uniform(0.5, 1.5) + random.uniform());
}

}  // namespace

ImageF makeProceduralRadiance(double width_m, double height_m, double texel_size,
                              const TextureRecipe& recipe, std::uint64_t seed) {
  const int width = std::max(1, static_cast<int>(std::ceil(width_m / texel_size)));
  const int height = std::max(1, static_cast<int>(std::ceil(height_m / texel_size)));
  ImageF image(width, height, recipe.mean);
  addFractalNoise(image, texel_size, 0, 0, width, height, recipe.largest_wavelength_m,
                  recipe.octaves, recipe.contrast, counterHash(seed, 1));

  SeededRandom random(counterHash(seed, 2));
  const double area = width_m * height_m;
  const int posters = randomCount(random, recipe.posters_per_m2 * area);
  for (int i = 0; i < posters; ++i) {
    const TexelRect r = randomRect(random, image, texel_size, 0.2, 1.2, 0.2, 1.0);
    fillRect(image, r, static_cast<float>(random.uniform(0.08, 0.95)));
    // Each poster has its own finer structure, so edges inside it are sharp and varied.
    addFractalNoise(image, texel_size, r.u0, r.v0, r.u1, r.v1, random.uniform(0.05, 0.4), 4,
                    static_cast<float>(random.uniform(0.05, 0.35)), random.bits());
    if (random.uniform() < 0.3) {  // a dark frame 2 cm wide
      const int border = std::max(1, static_cast<int>(0.02 / texel_size));
      const float frame = static_cast<float>(random.uniform(0.03, 0.2));
      fillRect(image, {r.u0, r.v0, r.u1, std::min(r.v0 + border, r.v1)}, frame);
      fillRect(image, {r.u0, std::max(r.v1 - border, r.v0), r.u1, r.v1}, frame);
      fillRect(image, {r.u0, r.v0, std::min(r.u0 + border, r.u1), r.v1}, frame);
      fillRect(image, {std::max(r.u1 - border, r.u0), r.v0, r.u1, r.v1}, frame);
    }
  }
  const int lines = randomCount(random, recipe.lines_per_m2 * area);
  for (int i = 0; i < lines; ++i) {
    const double thickness = random.uniform(0.01, 0.03);
    const double length = random.uniform(0.3, 2.0);
    const bool horizontal = random.uniform() < 0.5;
    const TexelRect r = horizontal ? randomRect(random, image, texel_size, length, length,
                                                thickness, thickness)
                                   : randomRect(random, image, texel_size, thickness,
                                                thickness, length, length);
    fillRect(image, r, random.uniform() < 0.6 ? 0.05f : 0.9f);
  }
  const int flat = randomCount(random, recipe.flat_patches_per_m2 * area);
  for (int i = 0; i < flat; ++i) {
    const TexelRect r = randomRect(random, image, texel_size, 0.6, 2.0, 0.5, 1.5);
    fillRect(image, r, static_cast<float>(random.uniform(0.3, 0.7)));
    addFractalNoise(image, texel_size, r.u0, r.v0, r.u1, r.v1, 0.5, 2, 0.005f, random.bits());
  }
  const int bright = randomCount(random, recipe.bright_patches_per_m2 * area);
  for (int i = 0; i < bright; ++i) {
    const TexelRect r = randomRect(random, image, texel_size, 0.3, 1.0, 0.3, 1.0);
    fillRect(image, r, static_cast<float>(random.uniform(0.93, 1.0)));
  }
  for (size_t i = 0; i < image.size(); ++i) {
    image.data()[i] = std::clamp(image.data()[i], kMinRadiance, 1.0f);
  }
  return image;
}

void pasteImagePoster(ImageF& radiance, double texel_size, const std::string& image_path,
                      double s_m, double t_m, double poster_w_m, double poster_h_m) {
  const ImageU8 poster = readImageU8(image_path);
  const int u0 = static_cast<int>(s_m / texel_size);
  const int v0 = static_cast<int>(t_m / texel_size);
  const int w = static_cast<int>(poster_w_m / texel_size);
  const int h = static_cast<int>(poster_h_m / texel_size);
  for (int v = std::max(v0, 0); v < std::min(v0 + h, radiance.height()); ++v) {
    const int pv = std::min((v - v0) * poster.height() / h, poster.height() - 1);
    for (int u = std::max(u0, 0); u < std::min(u0 + w, radiance.width()); ++u) {
      const int pu = std::min((u - u0) * poster.width() / w, poster.width() - 1);
      radiance(u, v) = std::max(static_cast<float>(poster(pu, pv)) / 255.f, kMinRadiance);
    }
  }
}

}  // namespace omnidso::synth
