#pragma once
// Elementary image operations for the pyramid and for pixel selection: 2×2 downsampling of
// images and validity masks, and intensity gradients.
//
// Pixel centres sit at integer coordinates, so a 2×2 mean puts level-(L+1) pixel u at
// level-L coordinate 2u + 0.5 (cameras/pyramid_scaling.hpp relies on this).

#include "omnidso/core/image.hpp"

namespace omnidso {

// Mean of each 2×2 block: out(u, v) = ¼ Σ in(2u + a, 2v + b), a, b ∈ {0, 1}. The output is
// floor(w/2) × floor(h/2); an odd last column/row is dropped.
ImageF downsample2x2(const ImageF& image);

// A downsampled pixel is valid (255) only if all 4 pixels it averages are valid (non-zero),
// so that no invalid intensity leaks into a coarser level; otherwise 0.
Mask downsampleMask(const Mask& mask);

struct ImageGradients {
  ImageF dx;  // ∂I/∂u
  ImageF dy;  // ∂I/∂v
};

// Central differences, dx = (I(u+1) − I(u−1)) / 2, one-sided at the borders
// (dx = I(1) − I(0) and I(w−1) − I(w−2)); zero along an axis of size 1. Exact for images
// linear in u and v.
ImageGradients computeGradients(const ImageF& image);

// ‖∇I‖² = dx² + dy² per pixel: the gradient weight w_p = c²/(c² + ‖∇I‖²) of eq. 5 and
// pixel selection use the squared norm.
ImageF gradientMagnitudeSquared(const ImageGradients& gradients);

}  // namespace omnidso
