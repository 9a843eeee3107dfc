// ImageSampler's bicubic sampling with gradient (image_sampler.hpp), out of line.
#include "omnidso/residuals/image_sampler.hpp"

namespace omnidso {

bool ImageSampler::sampleBicubicWithGradient(double u, double v, double* value, double* d_du,
                                             double* d_dv) const {
  if (!insideBicubicRegion(u, v) || !isContent(u, v)) return false;
  bicubic_->Evaluate(v, u, value, d_dv, d_du);  // (row, column)
  return true;
}

}  // namespace omnidso
