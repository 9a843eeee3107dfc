#pragma once
// Shared fixtures of the camera-model tests: realistic cameras for every model, random
// bearings in a model's domain, central differences, and the typed-test type list.

#include <omnidso/cameras/camera_models.hpp>

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace omnidso::test {

template <typename Tuple>
struct TupleToTypes;
template <typename... T>
struct TupleToTypes<std::tuple<T...>> {
  using type = ::testing::Types<T...>;
};

template <typename Model>
struct TestCamera {
  Model camera;
  int width;
  int height;
  std::string label;
};

// Realistic calibrations (values of the order of TUM VI, EuRoC and the fisheye rig of
// ../shared/data, scaled to a 640×480 or 480×480 image).
template <typename Model>
std::vector<TestCamera<Model>> realisticCameras();

template <typename Model>
TestCamera<Model> makeCamera(std::initializer_list<double> params, int width, int height,
                             const std::string& label) {
  typename Model::VecN p;
  std::copy(params.begin(), params.end(), p.data());
  return {Model(p), width, height, label};
}

template <>
inline std::vector<TestCamera<PinholeCamera<double>>> realisticCameras() {
  return {makeCamera<PinholeCamera<double>>({460.2, 458.7, 321.3, 238.6}, 640, 480, "vga")};
}
template <>
inline std::vector<TestCamera<UnifiedCamera<double>>> realisticCameras() {
  // ξ < 1: corners at ~115° from the axis; ξ > 1: pixels up to the fold at 131.8°.
  return {makeCamera<UnifiedCamera<double>>({190.3, 189.7, 240.6, 239.2, 0.95}, 480, 480,
                                            "xi<1"),
          makeCamera<UnifiedCamera<double>>({200.4, 199.8, 239.7, 240.3, 1.5}, 480, 480,
                                            "xi>1")};
}
template <>
inline std::vector<TestCamera<ExtendedUnifiedCamera<double>>> realisticCameras() {
  return {makeCamera<ExtendedUnifiedCamera<double>>({175.4, 175.1, 240.3, 239.6, 0.62, 1.05},
                                                    480, 480, "tumvi-like")};
}
template <>
inline std::vector<TestCamera<DoubleSphereCamera<double>>> realisticCameras() {
  return {makeCamera<DoubleSphereCamera<double>>({150.2, 149.8, 240.1, 239.3, -0.18, 0.59},
                                                 480, 480, "tumvi-like")};
}
template <>
inline std::vector<TestCamera<KannalaBrandtCamera<double>>> realisticCameras() {
  return {makeCamera<KannalaBrandtCamera<double>>(
      {179.2, 179.0, 239.8, 240.4, 0.0034823894, 0.000715034845, -0.00205323614,
       0.000202936736},
      480, 480, "tumvi-like")};
}
// TUM monoVO's camera.txt (relative: 0.349153 0.543105 0.49826 0.498311 0.934785) in pixels
// on its 1280×1024 images (fx·w, fy·h, cx·w − 0.5, cy·h − 0.5; corners ≈ 91° off-axis), and
// the same relative calibration on a 640×480 image (non-square pixels: fy/fx ≈ 1.17).
template <>
inline std::vector<TestCamera<FovCamera<double>>> realisticCameras() {
  return {makeCamera<FovCamera<double>>({446.91584, 556.13952, 637.2728, 509.770464, 0.934785},
                                        1280, 1024, "tum-monovo"),
          makeCamera<FovCamera<double>>({223.45792, 260.6904, 318.3864, 238.68928, 0.934785},
                                        640, 480, "tum-monovo-640x480")};
}
template <>
inline std::vector<TestCamera<PinholeRadTanCamera<double>>> realisticCameras() {
  return {makeCamera<PinholeRadTanCamera<double>>(
      {458.654, 457.296, 327.2, 248.4, -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05},
      640, 480, "euroc-like")};
}
template <>
inline std::vector<TestCamera<UnifiedRadTanCamera<double>>> realisticCameras() {
  return {makeCamera<UnifiedRadTanCamera<double>>(
      {204.46, 205.24, 315.14, 240.0, 1.05343, -0.0082879, 0.0117789, 0.0228246, -0.0041849},
      640, 480, "mei-rig")};
}

// A unit bearing uniform on the sphere cap of half-angle max_angle around +z.
inline Eigen::Vector3d randomBearing(std::mt19937& rng, double max_angle) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double cos_min = std::cos(max_angle);
  const double cos_theta = 1.0 - uniform(rng) * (1.0 - cos_min);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * M_PI * uniform(rng);
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// Jacobian tests keep further away: the unprojection has a square-root singularity at the
// fold (∂r/∂θ = 0), where the truncation error of any difference scheme grows as (h/δ)^k
// with δ the pixel distance to the fold; 0.2 rad keeps δ at several pixels.
inline constexpr double kJacobianBoundaryMargin = 0.2;

// Angle test bearings keep from the domain boundary: near the fold (∂r/∂θ = 0) the bearing
// round trip loses accuracy as 1/(∂r/∂θ) and central differences straddle the boundary.
inline constexpr double kBoundaryMargin = 0.05;

template <typename Model>
double testMaxAngle(const Model& camera, double margin) {
  return std::min(static_cast<double>(camera.maxAngleFromAxis()), M_PI) - margin;
}

// Random valid 3D points (projectable bearings at distances 0.5–20 m) whose pixel lies
// within the image enlarged by half its size on every side: the calibrated region the
// models are used in (radtan's r⁴ term is meaningless far outside it).
template <typename Model>
std::vector<Eigen::Vector3d> randomValidPoints(const TestCamera<Model>& tc, int count,
                                               unsigned seed,
                                               double margin = kBoundaryMargin) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> distance(0.5, 20.0);
  const double max_angle = testMaxAngle(tc.camera, margin);
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < count) {
    const Eigen::Vector3d p = randomBearing(rng, max_angle) * distance(rng);
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    if (!tc.camera.project(p, uv)) continue;
    if (uv.x() < -0.5 * tc.width || uv.x() > 1.5 * tc.width || uv.y() < -0.5 * tc.height ||
        uv.y() > 1.5 * tc.height) {
      continue;
    }
    points.push_back(p);
  }
  return points;
}

// Derivative of f: Rⁿ → Rᵐ (f returns false where undefined) by the fourth-order central
// difference (−f(x+2h) + 8f(x+h) − 8f(x−h) + f(x−2h))/(12h), with a step per input
// (jacobianSteps). Its truncation error is h⁴ f⁽⁵⁾/30, rounding ~1.5 ε|f|/h: both far
// below the 1e-6 the tests ask for with those steps.
template <int M, int N, typename Function>
Eigen::Matrix<double, M, N> numericJacobian(const Function& f,
                                            const Eigen::Matrix<double, N, 1>& x,
                                            const Eigen::Matrix<double, N, 1>& steps) {
  Eigen::Matrix<double, M, N> J;
  for (int i = 0; i < N; ++i) {
    const double h = steps[i];
    Eigen::Matrix<double, M, 1> sum = Eigen::Matrix<double, M, 1>::Zero();
    for (const auto& [offset, weight] : {std::pair{2.0, -1.0}, std::pair{1.0, 8.0},
                                         std::pair{-1.0, -8.0}, std::pair{-2.0, 1.0}}) {
      Eigen::Matrix<double, N, 1> xs = x;
      xs[i] += offset * h;
      Eigen::Matrix<double, M, 1> fs = Eigen::Matrix<double, M, 1>::Zero();
      EXPECT_TRUE(f(xs, fs)) << "numeric differentiation left the domain";
      sum += weight * fs;
    }
    J.col(i) = sum / (12.0 * h);
  }
  return J;
}

// Steps: each input moves the output by about output_step (1e-2 px for pixels, 1e-4 rad
// for bearings), judged from the column's size: h_i = output_step/‖∂f/∂x_i‖. Then rounding
// contributes ~ε|f|/output_step ≤ 1e-11 relative and truncation (output_step/scale)⁴ with
// scale the focal length or a radian, whatever the input's own units: a distortion
// coefficient acts through θ⁹ or r⁵ and can be a thousand times more or less sensitive
// than its value suggests. The step is capped at 1e-3·max(|x_i|, 1) where the output barely
// depends on x_i (distortion terms near the axis), so the input stays in range.
inline constexpr double kPixelOutputStep = 1e-2;
inline constexpr double kBearingOutputStep = 1e-4;
template <int M, int N>
Eigen::Matrix<double, N, 1> jacobianSteps(const Eigen::Matrix<double, N, 1>& x,
                                          const Eigen::Matrix<double, M, N>& analytic,
                                          double output_step) {
  Eigen::Matrix<double, N, 1> steps;
  for (int i = 0; i < N; ++i) {
    const double cap = 1e-3 * std::max(std::abs(x[i]), 1.0);
    const double sensitivity = analytic.col(i).norm();
    steps[i] = sensitivity * cap > output_step ? output_step / sensitivity : cap;
  }
  return steps;
}

// Largest per-column relative difference; a column that vanishes is measured against the
// matrix as a whole (1e-3 of its norm), so exact zeros compare in absolute terms.
template <typename DerivedA, typename DerivedB>
double columnRelativeError(const Eigen::MatrixBase<DerivedA>& a,
                           const Eigen::MatrixBase<DerivedB>& b) {
  double worst = 0.0;
  const double floor = 1e-3 * std::max(a.norm(), 1e-300);
  for (int j = 0; j < a.cols(); ++j) {
    const double scale = std::max(a.col(j).norm(), floor);
    worst = std::max(worst, (a.col(j) - b.col(j)).norm() / scale);
  }
  return worst;
}

}  // namespace omnidso::test
