#pragma once
// Bilinear sampling of float images at sub-pixel positions (u, v) = (column, row), pixel
// centres at integer coordinates (docs/architecture.md).
//
// The interpolant inside the cell [u0, u0+1] × [v0, v0+1], with fu = u − u0, fv = v − v0:
//   I(u, v) = (1−fv)·((1−fu)·I00 + fu·I10) + fv·((1−fu)·I01 + fu·I11)
//   ∂I/∂u   = (1−fv)·(I10 − I00) + fv·(I11 − I01)
//   ∂I/∂v   = (1−fu)·(I01 − I00) + fu·(I11 − I10)
// where Iab = I(u0 + a, v0 + b). The cell is u0 = floor(u), clamped to w − 2 so that the
// last column/row (u = w − 1) is reached from the left cell with fu = 1. On a cell edge the
// derivative is therefore the one of the cell to the right/below (or the last cell at the
// far border) — the same for the templated and the analytic version, so that autodiff
// residuals and hand-derived residuals agree everywhere.
//
// sampleBilinear is a template so that it runs on double, float and ceres::Jet without this
// header including Ceres: the cell index needs the scalar part of the coordinate, which
// scalarPart() gives (an overload for plain floating types and one for any type with a
// member `.a`, as ceres::Jet has).

#include <algorithm>
#include <cmath>

#include "omnidso/core/image.hpp"

namespace omnidso {

inline double scalarPart(double x) { return x; }
inline double scalarPart(float x) { return static_cast<double>(x); }
template <typename T>
auto scalarPart(const T& x) -> decltype(static_cast<double>(x.a)) {
  return static_cast<double>(x.a);
}

// The integer cell of a bilinear lookup: the top-left neighbour (u0, v0), the bottom-right
// (u1, v1) (equal to u0/v0 on a 1-pixel-wide image), or false if (u, v) lies outside
// [0, w−1] × [0, h−1] or is not finite.
struct BilinearCell {
  int u0 = 0;
  int v0 = 0;
  int u1 = 0;
  int v1 = 0;
};

inline bool bilinearCell(int width, int height, double u, double v, BilinearCell* cell) {
  // The negated comparisons are false for NaN, so NaN is rejected too.
  if (!(u >= 0.0 && v >= 0.0 && u <= width - 1.0 && v <= height - 1.0)) return false;
  if (!std::isfinite(u) || !std::isfinite(v)) return false;
  cell->u0 = std::min(static_cast<int>(std::floor(u)), std::max(width - 2, 0));
  cell->v0 = std::min(static_cast<int>(std::floor(v)), std::max(height - 2, 0));
  cell->u1 = std::min(cell->u0 + 1, width - 1);
  cell->v1 = std::min(cell->v0 + 1, height - 1);
  return true;
}

// Whether all four pixels of a bilinear cell are content in `content` (image-sized, non-zero =
// content); no mask means the whole image is content. A sample whose footprint touches a
// pixel without content (the black surround of a fisheye image, content_mask.hpp) mixes
// scene and surround and is rejected like one outside the image.
inline bool cellIsContent(const Mask* content, const BilinearCell& c) {
  if (content == nullptr) return true;
  const Mask& m = *content;
  return m(c.u0, c.v0) != 0 && m(c.u1, c.v0) != 0 && m(c.u0, c.v1) != 0 && m(c.u1, c.v1) != 0;
}

// The bilinear blend of image `img` over cell `c` at fractions (fu, fv) of the cell:
// (1 − fv)((1 − fu) I00 + fu I10) + fv((1 − fu) I01 + fu I11). Several images sampled at one
// point (an image and its gradient images) share the cell and the fractions.
template <typename T>
T bilinearBlend(const ImageF& img, const BilinearCell& c, const T& fu, const T& fv) {
  const T i00 = T(static_cast<double>(img(c.u0, c.v0)));
  const T i10 = T(static_cast<double>(img(c.u1, c.v0)));
  const T i01 = T(static_cast<double>(img(c.u0, c.v1)));
  const T i11 = T(static_cast<double>(img(c.u1, c.v1)));
  const T one(1.0);
  return (one - fv) * ((one - fu) * i00 + fu * i10) + fv * ((one - fu) * i01 + fu * i11);
}

// Bilinear value at (u, v); false (value untouched) outside the image, for non-finite
// coordinates, or where the footprint leaves `content` (optional, image-sized). For
// T = ceres::Jet the derivative parts follow the formula above.
template <typename T>
bool sampleBilinear(const ImageF& img, const T& u, const T& v, T* value,
                    const Mask* content = nullptr) {
  BilinearCell c;
  if (!bilinearCell(img.width(), img.height(), scalarPart(u), scalarPart(v), &c)) return false;
  if (!cellIsContent(content, c)) return false;
  const T fu = u - T(static_cast<double>(c.u0));
  const T fv = v - T(static_cast<double>(c.v0));
  *value = bilinearBlend(img, c, fu, fv);
  return true;
}

// Value and the exact partial derivatives of the bilinear interpolant (formulas above).
// Any of the output pointers may be null. `content` as for sampleBilinear.
inline bool sampleBilinearWithGradient(const ImageF& img, double u, double v, double* value,
                                       double* d_du, double* d_dv,
                                       const Mask* content = nullptr) {
  BilinearCell c;
  if (!bilinearCell(img.width(), img.height(), u, v, &c)) return false;
  if (!cellIsContent(content, c)) return false;
  const double fu = u - c.u0;
  const double fv = v - c.v0;
  const double i00 = img(c.u0, c.v0);
  const double i10 = img(c.u1, c.v0);
  const double i01 = img(c.u0, c.v1);
  const double i11 = img(c.u1, c.v1);
  if (value) {
    *value = (1.0 - fv) * ((1.0 - fu) * i00 + fu * i10) + fv * ((1.0 - fu) * i01 + fu * i11);
  }
  if (d_du) *d_du = (1.0 - fv) * (i10 - i00) + fv * (i11 - i01);
  if (d_dv) *d_dv = (1.0 - fu) * (i01 - i00) + fu * (i11 - i10);
  return true;
}

// The bilinear value with the image gradient taken as the bilinear blend of central
// differences at the cell's four pixels,
//   g_u(x, y) = (I(x+1, y) − I(x−1, y)) / 2   (one-sided at the image's and the content's
//                                              borders),
//   ∂I/∂u ≈ (1−fv)·((1−fu)·g_u00 + fu·g_u10) + fv·((1−fu)·g_u01 + fu·g_u11),   likewise ∂I/∂v,
// the gradient the original DSO gives its Jacobians. The interpolant's own derivative
// (sampleBilinearWithGradient) is a forward difference across the cell, constant within it
// and jumping at every pixel edge; the blend of central differences is continuous and exact
// for images quadratic in u and v. It is not the derivative of the value returned, so a
// Gauss–Newton step with it does not stop at the bilinear cost's minimum, and residuals using
// it fail a numeric gradient check by design (ImageGradient::kCentralDifferences,
// photometric_residual.hpp). Measured, mechanism not established: in the window's solve
// (`window.central_difference_gradients`) it halved the keyframe ATE of H12p, the independent
// renderer's 90° pinhole; bicubic sampling, smooth and exact for its own cost, did not
// (docs/performance.md, "The image gradient in the Jacobians").
inline bool sampleBilinearWithCentralGradient(const ImageF& img, double u, double v,
                                              double* value, double* d_du, double* d_dv,
                                              const Mask* content = nullptr) {
  BilinearCell c;  // the value and the validity as sampleBilinearWithGradient's
  if (!bilinearCell(img.width(), img.height(), u, v, &c) || !cellIsContent(content, c))
    return false;
  const double fu = u - c.u0, fv = v - c.v0;
  if (value) *value = bilinearBlend(img, c, fu, fv);
  const int w = img.width(), h = img.height();
  // The difference along (dx, dy) at pixel (x, y): central, or one-sided where a neighbour is
  // outside the image or the content (a fisheye's black surround), so that the circle's edge
  // never enters; 0 where neither neighbour is usable.
  const auto difference = [&](int x, int y, int dx, int dy) {
    const auto usable = [&](int nx, int ny) {
      return nx >= 0 && ny >= 0 && nx < w && ny < h &&
             (content == nullptr || (*content)(nx, ny) != 0);
    };
    const bool before = usable(x - dx, y - dy), after = usable(x + dx, y + dy);
    const int steps = int{before} + int{after};
    if (steps == 0) return 0.0;
    const float a = before ? img(x - dx, y - dy) : img(x, y);  // the difference in float, as
    const float b = after ? img(x + dx, y + dy) : img(x, y);   // the pixels' own precision
    return (b - a) / static_cast<double>(steps);
  };
  const auto blend = [fu, fv, &c](auto&& g) {
    return (1.0 - fv) * ((1.0 - fu) * g(c.u0, c.v0) + fu * g(c.u1, c.v0)) +
           fv * ((1.0 - fu) * g(c.u0, c.v1) + fu * g(c.u1, c.v1));
  };
  if (d_du) *d_du = blend([&](int x, int y) { return difference(x, y, 1, 0); });
  if (d_dv) *d_dv = blend([&](int x, int y) { return difference(x, y, 0, 1); });
  return true;
}

// True iff (u, v) is inside the image and all 4 neighbours used by the bilinear lookup are
// valid (non-zero) in the mask.
inline bool isValidBilinear(const Mask& mask, double u, double v) {
  BilinearCell c;
  if (!bilinearCell(mask.width(), mask.height(), u, v, &c)) return false;
  return cellIsContent(&mask, c);
}

}  // namespace omnidso
