#pragma once
// Shared vocabulary of the photometric residuals (paper eq. 5–7): the host-side data taken
// when a residual is created, the observation that ties it to a target image, the validity
// status, and DSO's default constants.
//
// For a point hosted in frame i at pixel p with inverse distance d = 1/‖x‖ (not inverse
// depth, so that points behind a fisheye camera are representable) and each pattern
// offset o (residual_pattern.hpp):
//   b_o   = π⁻¹(p + o)                         unit bearing in the host camera
//   x̃_o   = R b_o + d t                        = d · (R b_o / d + t)          (eq. 6)
//   p'_o  = π(x̃_o)
//   r_o   = √w_o · [(I_j[p'_o] − b_j) − (t_j e^{a_j}) / (t_i e^{a_i}) · (I_i[p + o] − b_i)]
//   w_o   = c² / (c² + ‖∇I_i(p + o)‖²)                                          (eq. 5)
// with [R t] = T_target_host = T_world_target⁻¹ · T_world_host (the paper's T_j T_i⁻¹ of
// eq. 7 written with T = T_cam_world; the parameter blocks hold T_world_cam). Every central
// model's π is invariant to a positive scale of its argument, so π(x̃) = π(R b/d + t) for
// d > 0, and d = 0 (a point at infinity) stays finite; d < 0 is rejected.
//
// Huber norm: DSO applies it per pixel; Ceres's LossFunction acts on the whole block's
// squared norm, so a per-pixel Huber cannot be expressed exactly. We use
// ceres::HuberLoss(k·√N) on the block (k = 9 intensity units as DSO): it equals the
// per-pixel Huber when all N pixels carry the same error, and is quadratic while the
// block's RMS error is below k (makePhotometricLoss).

#include <Eigen/Core>
#include <array>

#include "omnidso/core/image.hpp"
#include "omnidso/core/image_ops.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace ceres {
class LossFunction;
}

namespace omnidso {

// DSO's gradient-weight constant: w = c² / (c² + ‖∇I‖²) with c = 50 intensity units per
// pixel (DSO's setting_outlierTHSumComponent = 50²), and its Huber threshold of 9.
inline constexpr double kDsoGradientWeightC = 50.0;
inline constexpr double kDsoHuberThreshold = 9.0;
// DSO's outlier energy per pattern pixel (12²): a residual above it is an outlier, and an
// out-of-bounds residual costs exactly this much (out_of_bounds_penalty.hpp).
inline constexpr double kDsoOutlierEnergyPerPixel = 12.0 * 12.0;

enum class DifferentiationMode { kAutodiff, kAnalytic };

// Target-image sampling. Bicubic is ceres::BiCubicInterpolator (Catmull–Rom) on a
// ceres::Grid2D; it needs a 4×4 footprint, so its valid region is one pixel smaller.
enum class ImageInterpolation { kBilinear, kBicubic };

// The image gradient in a hand-derived Jacobian, for bilinear sampling (bicubic always uses
// its interpolant's derivative): kInterpolant, the exact derivative of the interpolated
// value (core/interpolation.hpp), which numeric gradient checks and autodiff agree with;
// kCentralDifferences, central differences blended bilinearly (DSO's; the settings
// window. / activation. / tracker. / initializer.central_difference_gradients, off by default;
// sampleBilinearWithCentralGradient has the measurements).
enum class ImageGradient { kInterpolant, kCentralDifferences };
// The modules' settings `*.central_difference_gradients` as an ImageGradient.
inline ImageGradient imageGradient(bool central_differences) {
  return central_differences ? ImageGradient::kCentralDifferences : ImageGradient::kInterpolant;
}

enum class PhotometricStatus {
  kValid,
  kNegativeInverseDistance,  // d < 0
  kHostOutsideDomain,        // a host pattern pixel does not unproject
  kBehindCamera,             // z ≤ 0 in a target model that sees nothing behind it
  kOutsideDomain,            // projection failed otherwise (e.g. beyond UCM's fold)
  kOutsideImage,             // the interpolation footprint leaves the target image
};

const char* toString(PhotometricStatus status);

// Why a projection failed: kBehindCamera where the model sees nothing with z ≤ 0 (largest
// angle from the axis ≤ 90°, e.g. pinhole) and the point is there; kOutsideDomain otherwise
// (e.g. beyond UCM's fold, which for ξ > 0 lies behind the camera but is a domain limit).
template <typename Camera, typename Vec3>
PhotometricStatus projectionFailure(const Camera& camera, const Vec3& point) {
  constexpr double kRightAngle = 1.5707963267948966;
  return point.z() <= 0.0 && camera.maxAngleFromAxis() <= kRightAngle
             ? PhotometricStatus::kBehindCamera
             : PhotometricStatus::kOutsideDomain;
}

// Host-side data, taken at creation on the pyramid level the residual is evaluated on.
template <int N>
struct HostPatch {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // p, in pixels of that level
  int spread = 1;  // the pattern's step in pixels (residual_pattern.hpp, spreadOffset)
  std::array<double, N> intensity{};                // I_i[p + o]
  std::array<double, N> sqrt_weight{};              // √w_o
};

// Samples the host image and its gradients (bilinear) at p + spread · o (residual_pattern.hpp,
// spreadOffset; spread ≥ 1, 1 is the pattern as defined). Throws omnidso::Error
// naming the pixel when a pattern pixel leaves the image. The weight is eq. 5's,
// w = c² / (c² + ‖∇I‖²). With `encoding_slope` (s = ∂I/∂E of the host level,
// ImagePyramid::encodingSlope) it is read in the camera's encoding, where noise added after
// the response is uniform (camera_encoding.hpp): the residual r_E counts as r_I ≈ s r_E and the
// gradient as s ∇E, so √w = s · c / √(c² + s² ‖∇E‖²). Without it (nullptr) s = 1, right when
// the noise is uniform in E. Which holds depends on where the camera adds its noise
// (camera_encoding.hpp): on the independent renderer's images weighing by s took D2's 90° crop
// from 4.2–6.5 % to 0.3–1.1 %, and made the own preset C's full image 8–10× worse, through the
// weights' scale against the window's fixed outlier bound (docs/performance.md, "Residuals
// weighed in the camera's encoding", "The noise measured; …"). Setting `noise_in_encoding`, off.
template <int N>
HostPatch<N> makeHostPatch(const ImageF& host_image, const ImageGradients& host_gradients,
                           const Eigen::Vector2d& pixel,
                           double gradient_weight_c = kDsoGradientWeightC,
                           const ImageF* encoding_slope = nullptr, int spread = 1);

// How far a host patch reaches from its pixel: the pattern on steps of `spread` pixels and one
// more for the bilinear footprint (the central differences of the host's gradients).
template <int N>
constexpr int hostPatchReachPx(int spread = 1) {
  return patternRadius<N>() * spread + 1;
}

// Whether the pattern, on steps of `spread` pixels, around `pixel` (pixels of `image`), with the
// bilinear footprint, lies inside the image: the condition makeHostPatch needs.
template <int N>
bool hostPatchFits(const ImageF& image, const Eigen::Vector2d& pixel, int spread = 1) {
  const double margin = hostPatchReachPx<N>(spread);
  return pixel.x() >= margin && pixel.y() >= margin && pixel.x() <= image.width() - 1 - margin &&
         pixel.y() <= image.height() - 1 - margin;
}

// One point observed in one target frame, on pyramid level `level`.
template <int N>
struct PhotometricObservation {
  HostPatch<N> host;
  const ImageF* target_image = nullptr;  // level `level` of the target frame; not owned
  // Where that level has content (ImagePyramid::content), or nullptr for the whole image;
  // not owned. A sample touching a pixel without content is out of the image.
  const Mask* target_content = nullptr;
  double host_exposure = 1.0;            // t_i
  double target_exposure = 1.0;          // t_j
  // The intrinsics block always holds the level-0 parameters; the residual scales them
  // to this level (pyramid_scaling.hpp) and chains the scaling into the Jacobian.
  int level = 0;
  ImageInterpolation interpolation = ImageInterpolation::kBilinear;
  ImageGradient gradient = ImageGradient::kInterpolant;
};

// ceres::HuberLoss(huber_threshold · √pattern_size), owned by the caller (see above).
ceres::LossFunction* makePhotometricLoss(int pattern_size,
                                         double huber_threshold = kDsoHuberThreshold);

}  // namespace omnidso
