#pragma once
// Shared fixtures of the residual tests: one tag type per camera model (its test intrinsics
// and the factory calls, so that typed tests reach the explicitly instantiated templates),
// an analytic smooth texture for gradient checks, and pose helpers.

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <memory>
#include <optional>

#include "omnidso/cameras/double_sphere.hpp"
#include "omnidso/cameras/extended_unified.hpp"
#include "omnidso/cameras/fov.hpp"
#include "omnidso/cameras/kannala_brandt.hpp"
#include "omnidso/cameras/pinhole.hpp"
#include "omnidso/cameras/unified.hpp"
#include "omnidso/core/image.hpp"
#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/photometric_cost.hpp"
#include "omnidso/residuals/residual_pattern.hpp"
#include "omnidso/residuals/tracking_residual.hpp"

namespace omnidso::test {

// Gradient checks of the hand-derived kernels. GradientChecker differentiates with Ridders'
// method. Its default first step (1e-2·|x|) rotates a pose block by tens of degrees and leaves
// the image; with 1e-6·|x| the largest step moves a target pixel by ≲ 1e-3 px. The bilinear
// interpolant is smooth only inside a pixel cell, so test points keep every target pixel
// kCellEdgeMargin = 0.02 px (≫ 1e-3 px) from the cell edges; there Ridders' extrapolation is
// accurate to ~1e-9 relative, and 1e-5 relative leaves room for the smallest entries.
inline constexpr double kGradientCheckPrecision = 1e-5;
inline constexpr double kRiddersInitialStep = 1e-6;
inline constexpr double kCellEdgeMargin = 0.02;

// Test images are 320 × 240; every model's intrinsics put 90° off-axis about 95 px from the
// centre (except pinhole, ~80° field of view), so wide rays stay inside the image.
inline constexpr int kTestWidth = 320;
inline constexpr int kTestHeight = 240;

template <template <typename> class C>
struct ModelTag {
  template <typename S>
  using Camera = C<S>;
  static constexpr int kNumParams = C<double>::kNumParams;
  using Params = Eigen::Matrix<double, kNumParams, 1>;

  static Params params();
  static C<double> camera() { return C<double>(params()); }

  template <int N>
  static ceres::CostFunction* photometric(DifferentiationMode mode,
                                          const PhotometricObservation<N>& obs) {
    return makePhotometricCost<C, N>(mode, obs);
  }
  template <int N>
  static PhotometricStatus status(const PhotometricObservation<N>& obs,
                                  double const* const* parameters) {
    return photometricStatus<C, N>(obs, parameters);
  }
  template <int N>
  static ceres::CostFunction* tracking(DifferentiationMode mode, const C<double>& level_camera,
                                       const TrackingObservation<N>& obs) {
    return makeTrackingCost<C, N>(mode, level_camera, obs);
  }
  template <int N>
  static std::optional<TrackingObservation<N>> trackingObservation(const C<double>& camera,
                                                                   const HostPatch<N>& patch,
                                                                   double inverse_distance) {
    return makeTrackingObservation<C, N>(camera, patch, inverse_distance);
  }
};

template <>
inline ModelTag<PinholeCamera>::Params ModelTag<PinholeCamera>::params() {
  return Params(180.0, 175.0, 159.5, 119.5);
}
template <>
inline ModelTag<UnifiedCamera>::Params ModelTag<UnifiedCamera>::params() {
  Params p;
  p << 92.0, 90.0, 160.2, 119.7, 1.05;  // ξ ≥ 1: sees up to acos(−1/ξ) ≈ 162° off-axis
  return p;
}
template <>
inline ModelTag<ExtendedUnifiedCamera>::Params ModelTag<ExtendedUnifiedCamera>::params() {
  Params p;
  p << 60.0, 59.0, 160.2, 119.7, 0.6, 1.1;
  return p;
}
template <>
inline ModelTag<DoubleSphereCamera>::Params ModelTag<DoubleSphereCamera>::params() {
  Params p;
  p << 50.0, 49.5, 160.2, 119.7, -0.2, 0.6;
  return p;
}
template <>
inline ModelTag<KannalaBrandtCamera>::Params ModelTag<KannalaBrandtCamera>::params() {
  Params p;
  p << 60.0, 59.5, 160.2, 119.7, 0.01, -0.005, 0.001, 0.0002;
  return p;
}
template <>
inline ModelTag<FovCamera>::Params ModelTag<FovCamera>::params() {
  Params p;
  p << 56.0, 55.5, 160.2, 119.7, 0.93;  // 90° off-axis at r_d = π/(2ω) ≈ 1.69: ≈ 94 px
  return p;
}

using Pinhole = ModelTag<PinholeCamera>;
using Ucm = ModelTag<UnifiedCamera>;
using Eucm = ModelTag<ExtendedUnifiedCamera>;
using Ds = ModelTag<DoubleSphereCamera>;
using Kb4 = ModelTag<KannalaBrandtCamera>;
using Fov = ModelTag<FovCamera>;

// I(u, v) = 128 + a sum of sines: smooth at the pixel scale (wavelengths ≥ 15 px) so that
// bilinear interpolation and numeric differences see a well-behaved function.
inline double smoothTextureValue(double u, double v) {
  return 128.0 + 40.0 * std::sin(0.11 * u + 0.05 * v) + 30.0 * std::cos(0.07 * u - 0.13 * v) +
         20.0 * std::sin(0.23 * u + 0.19 * v + 0.4) + 10.0 * std::cos(0.003 * u * v);
}

inline ImageF smoothTexture(int width, int height) {
  ImageF image(width, height);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) image(u, v) = static_cast<float>(smoothTextureValue(u, v));
  }
  return image;
}

inline SE3d poseFrom(double rx, double ry, double rz, double tx, double ty, double tz) {
  return SE3d(so3Exp(Eigen::Vector3d(rx, ry, rz)), Eigen::Vector3d(tx, ty, tz));
}

inline std::array<double, 7> poseBlock(const SE3d& pose) {
  std::array<double, 7> block;
  pose.toParameters(block.data());
  return block;
}

// All parameter blocks of one photometric residual, in the factory's order.
template <int K>
struct PhotometricBlocks {
  std::array<double, 7> host_pose;
  std::array<double, 7> target_pose;
  double inverse_distance = 0.5;
  std::array<double, 2> host_affine{0.0, 0.0};
  std::array<double, 2> target_affine{0.0, 0.0};
  Eigen::Matrix<double, K, 1> intrinsics;

  std::array<const double*, 6> pointers() const {
    return {host_pose.data(),   target_pose.data(),   &inverse_distance,
            host_affine.data(), target_affine.data(), intrinsics.data()};
  }
};

}  // namespace omnidso::test

namespace omnidso::test {

// The target pixels p'_o of a photometric residual (eq. 6), recomputed from the camera
// model for test preconditions; false if any pattern pixel does not project.
template <typename Tag, int N, int K>
bool targetPixels(const PhotometricObservation<N>& obs, const PhotometricBlocks<K>& blocks,
                  std::array<Eigen::Vector2d, static_cast<size_t>(N)>* pixels) {
  typename Tag::Params params = blocks.intrinsics;
  for (int i = 0; i < 4; ++i) {  // level scaling of fx fy cx cy (pyramid_scaling.hpp)
    const double s = 1.0 / (1 << obs.level);
    params[i] = i < 2 ? params[i] * s : (params[i] + 0.5) * s - 0.5;
  }
  const typename Tag::template Camera<double> camera(params);
  const SE3d T_target_host = SE3d::fromParameters(blocks.target_pose.data()).inverse() *
                             SE3d::fromParameters(blocks.host_pose.data());
  for (int o = 0; o < N; ++o) {
    const PatternOffset off = spreadOffset<N>(o, obs.host.spread);
    Eigen::Vector3d bearing;
    if (!camera.unproject(Eigen::Vector2d(obs.host.pixel.x() + off.du, obs.host.pixel.y() + off.dv),
                          bearing)) {
      return false;
    }
    const Eigen::Vector3d x = T_target_host.rotationMatrix() * bearing +
                              blocks.inverse_distance * T_target_host.translation();
    if (!camera.project(x, (*pixels)[o])) return false;
  }
  return true;
}

// The bilinear interpolant is smooth inside a pixel cell and only continuous across cell
// edges, so numeric differences are only comparable with exact derivatives where every
// target pixel stays `margin` away from integer coordinates.
template <size_t N>
bool awayFromCellEdges(const std::array<Eigen::Vector2d, N>& pixels, double margin) {
  for (const Eigen::Vector2d& p : pixels) {
    for (int i = 0; i < 2; ++i) {
      const double frac = p[i] - std::floor(p[i]);
      if (frac < margin || frac > 1.0 - margin) return false;
    }
  }
  return true;
}

}  // namespace omnidso::test
