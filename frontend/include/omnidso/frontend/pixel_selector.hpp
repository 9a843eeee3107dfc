#pragma once
// Candidate pixel selection as in DSO (Engel et al. 2018, Sec. 3.2 "Candidate point
// selection"), over the camera's validity mask so that the whole fisheye image is used:
//  1. Region-adaptive threshold: the image is split into 32×32 blocks; each block's
//     threshold is the median gradient magnitude ‖∇I‖ of its valid pixels plus a global
//     constant g_th (7 intensity units), smoothed over the 3×3 neighbouring blocks.
//  2. The image is split into d×d cells; in each, the valid pixel with the largest
//     |∇I · r| (r a random unit direction per cell, for diversity of gradient directions)
//     whose ‖∇I‖ passes the threshold is selected. Where a 2d×2d cell got nothing, its best
//     pixel on pyramid level 1 is taken against 0.75× the threshold, and likewise on level 2
//     for 4d×4d cells with 0.75² ×: weak-gradient regions still get a few points.
//  3. d is adapted (d ← d·√(n/N)) until the count n is within 20% of the desired N.
// Deterministic for a given seed.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <omnidso/core/image.hpp>
#include <omnidso/core/pyramid.hpp>
#include <vector>

namespace omnidso {

struct PixelSelectorOptions {
  int desired_points = 2000;
  int threshold_block_size = 32;
  double gradient_threshold_offset = 7.0;  // g_th
  double coarser_level_factor = 0.75;
  int border = 4;                // pixels kept free at the image border (pattern + footprint)
  int max_adaptation_rounds = 4;
  std::uint64_t seed = 0;
  // The camera's encoding, I = G(V E) for the corrected intensity E (camera_encoding.hpp; null:
  // linear; the odometry sets it from OdometryOptions::camera_encoding). With
  // `camera_encoding` the thresholds of steps 1–2 test ‖∇I‖ ≈ G′(V E) V ‖∇E‖, the gradient in
  // the camera's own encoding, where its noise is about uniform — as DSO selects (its
  // `gammaWeightsPixelSelect`, with V left out). In the linear intensities the bright half of
  // a gamma-encoded image holds most of the gradient, and the threshold's constant offset
  // starves the dark half (docs/performance.md, "Pixels selected in the camera's encoding").
  // The directional scores stay on ∇E. Off by default: on the development set it took D2's
  // crop from 6.2 to 1.4 % but the full image of D3 from 0.032 to 0.093 % (scale drift up to
  // +3.8 %) and D4's from 0.013 to 0.026 %; setting `selection.camera_encoding`.
  std::shared_ptr<const CameraEncoding> encoding;
  bool camera_encoding = false;
};

struct SelectedPixel {
  Eigen::Vector2i pixel;  // level 0
  int level = 0;          // pyramid level whose pass selected it (0, 1 or 2)
  float gradient = 0.f;   // ‖∇I‖ at level 0 as the thresholds read it (camera_encoding)
};

// `mask`: level-0 validity (non-zero = valid); an empty mask means the whole image. A pixel is
// only selected when its whole neighbourhood of radius `border` is valid.
std::vector<SelectedPixel> selectPixels(const ImagePyramid& pyramid, const Mask& mask,
                                        const PixelSelectorOptions& options);

// The region-adaptive threshold of step 1, one value per threshold block (row-major), from
// the level-0 gradient norm ‖∇I‖.
Image<float> gradientThresholdMap(const Image<float>& gradient_norm, const Mask& mask,
                                  int block_size, double offset);

}  // namespace omnidso
