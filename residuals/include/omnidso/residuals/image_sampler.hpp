#pragma once
// Sub-pixel sampling of a target image for the photometric residuals, the same function
// for Jets (autodiff) and for the hand-derived kernels (value + exact gradient), so that
// both differentiate the same interpolant:
//   bilinear: core/interpolation.hpp, valid on [0, w−1] × [0, h−1];
//   bicubic:  ceres::BiCubicInterpolator on ceres::Grid2D, valid on [1, w−2] × [1, h−2]
//             (its 4×4 footprint stays inside the image; Grid2D would clamp beyond).
// `content` (optional, image-sized): samples whose bilinear cell touches a pixel without
// content are rejected like samples outside the image (content_mask.hpp says why; for
// bicubic the central cell of the 4×4 footprint is checked).
// sampleWithGradient's gradient on the bilinear path: the interpolant's derivative or
// central differences blended bilinearly (ImageGradient, photometric_residual.hpp); Jets
// (sample) always differentiate the interpolant.
// The sampler keeps pointers to the image and the mask: both must outlive it.

#include <ceres/cubic_interpolation.h>

#include <memory>

#include "omnidso/core/image.hpp"
#include "omnidso/core/interpolation.hpp"
#include "omnidso/residuals/photometric_residual.hpp"

namespace omnidso {

class ImageSampler {
 public:
  ImageSampler(const ImageF& image, ImageInterpolation interpolation,
               const Mask* content = nullptr,
               ImageGradient gradient = ImageGradient::kInterpolant)
      : image_(&image), content_(content), interpolation_(interpolation), gradient_(gradient) {
    if (interpolation_ == ImageInterpolation::kBicubic) {
      grid_ = std::make_unique<Grid>(image.data(), 0, image.height(), 0, image.width());
      bicubic_ = std::make_unique<BiCubic>(*grid_);
    }
  }

  template <typename T>
  bool sample(const T& u, const T& v, T* value) const {
    if (interpolation_ == ImageInterpolation::kBilinear) {
      return sampleBilinear(*image_, u, v, value, content_);
    }
    if (!insideBicubicRegion(scalarPart(u), scalarPart(v)) ||
        !isContent(scalarPart(u), scalarPart(v)))
      return false;
    bicubic_->Evaluate(v, u, value);  // (row, column)
    return true;
  }

  bool sampleWithGradient(double u, double v, double* value, double* d_du, double* d_dv) const {
    if (interpolation_ == ImageInterpolation::kBilinear) {
      return gradient_ == ImageGradient::kCentralDifferences
                 ? sampleBilinearWithCentralGradient(*image_, u, v, value, d_du, d_dv, content_)
                 : sampleBilinearWithGradient(*image_, u, v, value, d_du, d_dv, content_);
    }
    return sampleBicubicWithGradient(u, v, value, d_du, d_dv);
  }

 private:
  // Out of line (image_sampler.cc): the bilinear path above, which every solver's residual
  // kernel calls per pattern pixel, then stays small enough to be inlined there.
  bool sampleBicubicWithGradient(double u, double v, double* value, double* d_du,
                                 double* d_dv) const;

  using Grid = ceres::Grid2D<float, 1>;
  using BiCubic = ceres::BiCubicInterpolator<Grid>;

  bool insideBicubicRegion(double u, double v) const {
    // Comparisons with NaN are false, so NaN is rejected too.
    return u >= 1.0 && v >= 1.0 && u <= image_->width() - 2.0 && v <= image_->height() - 2.0;
  }

  bool isContent(double u, double v) const {
    BilinearCell c;
    return content_ == nullptr ||
           (bilinearCell(image_->width(), image_->height(), u, v, &c) && cellIsContent(content_, c));
  }

  const ImageF* image_;
  const Mask* content_;
  ImageInterpolation interpolation_;
  ImageGradient gradient_;
  std::unique_ptr<Grid> grid_;
  std::unique_ptr<BiCubic> bicubic_;
};

}  // namespace omnidso
