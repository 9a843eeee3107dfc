// Camera-model micro-benchmarks: project, unproject and project with both Jacobians, in
// double and in ceres::Jet<double, 3 + kNumParams> (what an autodiff residual evaluates),
// for every model of camera_models.hpp. Inputs cycle through 1024 precomputed valid points
// or pixels so that branches and caches behave as in a residual kernel.
// Names: BM_<Operation><kName,scalar>, e.g. BM_Project<ucm,double>, BM_Project<kb4,jet>.

#include <omnidso/cameras/camera_models.hpp>

#include <benchmark/benchmark.h>
#include <ceres/jet.h>

#include <Eigen/Core>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace omnidso {
namespace {

constexpr int kNumInputs = 1024;  // a power of two: the index wraps with a mask

template <typename Model>
Model makeModel(std::initializer_list<double> values) {
  typename Model::VecN params;
  std::copy(values.begin(), values.end(), params.data());
  return Model(params);
}

// Realistic calibrations for a 480×480 (fisheye) or 640×480 (pinhole) image.
template <typename Model>
Model benchmarkCamera();
template <>
PinholeCamera<double> benchmarkCamera() {
  return makeModel<PinholeCamera<double>>({460.2, 458.7, 321.3, 238.6});
}
template <>
UnifiedCamera<double> benchmarkCamera() {
  return makeModel<UnifiedCamera<double>>({190.3, 189.7, 240.6, 239.2, 0.95});
}
template <>
ExtendedUnifiedCamera<double> benchmarkCamera() {
  return makeModel<ExtendedUnifiedCamera<double>>({175.4, 175.1, 240.3, 239.6, 0.62, 1.05});
}
template <>
DoubleSphereCamera<double> benchmarkCamera() {
  return makeModel<DoubleSphereCamera<double>>({150.2, 149.8, 240.1, 239.3, -0.18, 0.59});
}
template <>
KannalaBrandtCamera<double> benchmarkCamera() {
  return makeModel<KannalaBrandtCamera<double>>(
      {179.2, 179.0, 239.8, 240.4, 0.00348, 0.000715, -0.00205, 0.000203});
}
template <>
FovCamera<double> benchmarkCamera() {
  // TUM monoVO's relative calibration on a 640×480 image.
  return makeModel<FovCamera<double>>({223.458, 260.690, 318.386, 238.689, 0.934785});
}
template <>
PinholeRadTanCamera<double> benchmarkCamera() {
  return makeModel<PinholeRadTanCamera<double>>(
      {458.654, 457.296, 327.2, 248.4, -0.2834, 0.07396, 0.00019359, 1.76e-05});
}
template <>
UnifiedRadTanCamera<double> benchmarkCamera() {
  return makeModel<UnifiedRadTanCamera<double>>(
      {204.46, 205.24, 315.14, 240.0, 1.05343, -0.0082879, 0.0117789, 0.0228246, -0.0041849});
}

// Valid points whose pixels fall inside a 480×480 region around the principal point
// (fixed seed: every run measures the same inputs).
template <typename Model>
void makeInputs(const Model& camera, std::vector<Eigen::Vector3d>& points,
                std::vector<Eigen::Vector2d>& pixels) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::uniform_real_distribution<double> distance(0.5, 20.0);
  const Eigen::Vector2d centre = camera.params().template segment<2>(2);
  while (static_cast<int>(points.size()) < kNumInputs) {
    const Eigen::Vector3d direction(coordinate(rng), coordinate(rng), coordinate(rng));
    if (direction.norm() < 1e-3) continue;
    const Eigen::Vector3d p = direction.normalized() * distance(rng);
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    Eigen::Vector3d bearing = Eigen::Vector3d::Zero();
    if (!camera.project(p, uv) || (uv - centre).cwiseAbs().maxCoeff() > 240.0 ||
        !camera.unproject(uv, bearing)) {
      continue;
    }
    points.push_back(p);
    pixels.push_back(uv);
  }
}

template <typename Model>
void projectDouble(benchmark::State& state) {
  const Model camera = benchmarkCamera<Model>();
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  makeInputs(camera, points, pixels);
  Eigen::Vector2d uv;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera.project(points[i], uv));
    benchmark::DoNotOptimize(uv);
    i = (i + 1) & (kNumInputs - 1);
  }
}

template <typename Model>
void unprojectDouble(benchmark::State& state) {
  const Model camera = benchmarkCamera<Model>();
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  makeInputs(camera, points, pixels);
  Eigen::Vector3d bearing;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera.unproject(pixels[i], bearing));
    benchmark::DoNotOptimize(bearing);
    i = (i + 1) & (kNumInputs - 1);
  }
}

template <typename Model>
void projectWithJacobiansDouble(benchmark::State& state) {
  const Model camera = benchmarkCamera<Model>();
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  makeInputs(camera, points, pixels);
  Eigen::Vector2d uv;
  typename Model::Mat23 d_uv_d_p;
  typename Model::Mat2N d_uv_d_params;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera.project(points[i], uv, &d_uv_d_p, &d_uv_d_params));
    benchmark::DoNotOptimize(uv);
    benchmark::DoNotOptimize(d_uv_d_p);
    benchmark::DoNotOptimize(d_uv_d_params);
    i = (i + 1) & (kNumInputs - 1);
  }
}

// Jet<double, 3 + kNumParams>: derivatives with respect to the point and every parameter.
template <typename Model>
using BenchJet = ceres::Jet<double, 3 + Model::kNumParams>;

template <typename Model>
auto jetCamera(const Model& camera) {
  auto jet_camera = camera.template cast<BenchJet<Model>>();
  for (int j = 0; j < Model::kNumParams; ++j) jet_camera.params()[j].v[3 + j] = 1.0;
  return jet_camera;
}

template <typename Model>
void projectJet(benchmark::State& state) {
  using Jet = BenchJet<Model>;
  const Model camera = benchmarkCamera<Model>();
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  makeInputs(camera, points, pixels);
  const auto jet_camera = jetCamera(camera);
  std::vector<Eigen::Matrix<Jet, 3, 1>> jet_points(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    for (int r = 0; r < 3; ++r) jet_points[k][r] = Jet(points[k][r], r);
  }
  Eigen::Matrix<Jet, 2, 1> uv;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(jet_camera.project(jet_points[i], uv));
    benchmark::DoNotOptimize(uv);
    i = (i + 1) & (kNumInputs - 1);
  }
}

template <typename Model>
void unprojectJet(benchmark::State& state) {
  using Jet = BenchJet<Model>;
  const Model camera = benchmarkCamera<Model>();
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> pixels;
  makeInputs(camera, points, pixels);
  const auto jet_camera = jetCamera(camera);
  std::vector<Eigen::Matrix<Jet, 2, 1>> jet_pixels(pixels.size());
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    for (int r = 0; r < 2; ++r) jet_pixels[k][r] = Jet(pixels[k][r], r);
  }
  Eigen::Matrix<Jet, 3, 1> bearing;
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(jet_camera.unproject(jet_pixels[i], bearing));
    benchmark::DoNotOptimize(bearing);
    i = (i + 1) & (kNumInputs - 1);
  }
}

template <typename Model>
void registerModel() {
  const std::string name = Model::kName;
  benchmark::RegisterBenchmark(("BM_Project<" + name + ",double>").c_str(),
                               projectDouble<Model>);
  benchmark::RegisterBenchmark(("BM_Unproject<" + name + ",double>").c_str(),
                               unprojectDouble<Model>);
  benchmark::RegisterBenchmark(("BM_ProjectWithJacobians<" + name + ",double>").c_str(),
                               projectWithJacobiansDouble<Model>);
  benchmark::RegisterBenchmark(("BM_Project<" + name + ",jet>").c_str(), projectJet<Model>);
  benchmark::RegisterBenchmark(("BM_Unproject<" + name + ",jet>").c_str(),
                               unprojectJet<Model>);
}

template <typename... Models>
bool registerModels(std::tuple<Models...>*) {
  (registerModel<Models>(), ...);
  return true;
}

// Registration at static-initialisation time, as the BENCHMARK macros do.
[[maybe_unused]] const bool kCameraBenchmarksRegistered =
    registerModels(static_cast<AllCameraModels*>(nullptr));

}  // namespace
}  // namespace omnidso
