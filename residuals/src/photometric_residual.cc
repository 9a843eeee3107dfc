#include "omnidso/residuals/photometric_residual.hpp"

#include <ceres/loss_function.h>

#include <cmath>
#include <string>

#include "omnidso/core/error.hpp"
#include "omnidso/core/interpolation.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace omnidso {

const char* toString(PhotometricStatus status) {
  switch (status) {
    case PhotometricStatus::kValid:
      return "valid";
    case PhotometricStatus::kNegativeInverseDistance:
      return "negative inverse distance";
    case PhotometricStatus::kHostOutsideDomain:
      return "host pixel outside the camera model's domain";
    case PhotometricStatus::kBehindCamera:
      return "behind the target camera";
    case PhotometricStatus::kOutsideDomain:
      return "outside the camera model's domain";
    case PhotometricStatus::kOutsideImage:
      return "outside the target image";
  }
  return "unknown";
}

template <int N>
HostPatch<N> makeHostPatch(const ImageF& host_image, const ImageGradients& host_gradients,
                           const Eigen::Vector2d& pixel, double gradient_weight_c,
                           const ImageF* encoding_slope, int spread) {
  if (spread < 1)
    throw Error("makeHostPatch: the pattern's spread must be >= 1, got " + std::to_string(spread));
  HostPatch<N> patch;
  patch.pixel = pixel;
  patch.spread = spread;
  const double c_sq = gradient_weight_c * gradient_weight_c;
  for (int o = 0; o < N; ++o) {
    const PatternOffset offset = spreadOffset<N>(o, spread);
    const double u = pixel.x() + offset.du;
    const double v = pixel.y() + offset.dv;
    double gx = 0.0, gy = 0.0, s = 1.0;
    if (!sampleBilinearWithGradient(host_image, u, v, &patch.intensity[o], nullptr, nullptr) ||
        !sampleBilinearWithGradient(host_gradients.dx, u, v, &gx, nullptr, nullptr) ||
        !sampleBilinearWithGradient(host_gradients.dy, u, v, &gy, nullptr, nullptr) ||
        (encoding_slope &&
         !sampleBilinearWithGradient(*encoding_slope, u, v, &s, nullptr, nullptr))) {
      throw Error("makeHostPatch: pattern pixel (" + std::to_string(u) + ", " + std::to_string(v) +
                  ") of host pixel (" + std::to_string(pixel.x()) + ", " +
                  std::to_string(pixel.y()) + ") lies outside the host image");
    }
    // w = c² / (c² + ‖∇I_i‖²) (eq. 5); the residual carries √w. In the camera's encoding
    // (header): r_I = s r_E, ∇I = s ∇E.
    patch.sqrt_weight[o] =
        encoding_slope ? s * std::sqrt(c_sq / (c_sq + s * s * (gx * gx + gy * gy)))
                       : std::sqrt(c_sq / (c_sq + gx * gx + gy * gy));
  }
  return patch;
}

template HostPatch<1> makeHostPatch<1>(const ImageF&, const ImageGradients&, const Eigen::Vector2d&,
                                       double, const ImageF*, int);
template HostPatch<5> makeHostPatch<5>(const ImageF&, const ImageGradients&, const Eigen::Vector2d&,
                                       double, const ImageF*, int);
template HostPatch<8> makeHostPatch<8>(const ImageF&, const ImageGradients&, const Eigen::Vector2d&,
                                       double, const ImageF*, int);

ceres::LossFunction* makePhotometricLoss(int pattern_size, double huber_threshold) {
  return new ceres::HuberLoss(huber_threshold * std::sqrt(static_cast<double>(pattern_size)));
}

}  // namespace omnidso
