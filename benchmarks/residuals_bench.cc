// Residual + Jacobian evaluations per second of the photometric residual (pattern size 8)
// for every camera model, hand-derived ("Analytic") and autodiff ("Autodiff"), on a
// 640×480 smooth texture with 64 points spread over the image and a small relative motion,
// as in sliding-window bundle adjustment. All six parameter blocks request Jacobians.
// Compare: omnidso_benchmarks --benchmark_filter='Autodiff|Analytic'

#include <benchmark/benchmark.h>
#include <ceres/cost_function.h>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "omnidso/cameras/double_sphere.hpp"
#include "omnidso/cameras/extended_unified.hpp"
#include "omnidso/cameras/fov.hpp"
#include "omnidso/cameras/kannala_brandt.hpp"
#include "omnidso/cameras/pinhole.hpp"
#include "omnidso/cameras/unified.hpp"
#include "omnidso/core/se3.hpp"
#include "omnidso/residuals/photometric_cost.hpp"
#include "omnidso/residuals/residual_pattern.hpp"

namespace {

using omnidso::DifferentiationMode;
using omnidso::PhotometricObservation;
using omnidso::PhotometricStatus;

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr int kPatternSize = 8;
constexpr int kNumPoints = 64;

// One tag per camera model; the type name is the model's kName so that benchmark names
// read e.g. BM_PhotometricResidual_Analytic<ucm>. Intrinsics for 640×480 (fisheyes: 90°
// off-axis about 190 px from the centre).
template <template <typename> class C>
struct Model {
  using Params = Eigen::Matrix<double, C<double>::kNumParams, 1>;
  static ceres::CostFunction* make(DifferentiationMode mode,
                                   const PhotometricObservation<kPatternSize>& obs) {
    return omnidso::makePhotometricCost<C, kPatternSize>(mode, obs);
  }
  static PhotometricStatus status(const PhotometricObservation<kPatternSize>& obs,
                                  double const* const* parameters) {
    return omnidso::photometricStatus<C, kPatternSize>(obs, parameters);
  }
};
struct pinhole : Model<omnidso::PinholeCamera> {
  static Params params() { return Params(360.0, 350.0, 319.5, 239.5); }
};
struct ucm : Model<omnidso::UnifiedCamera> {
  static Params params() { return (Params() << 184.0, 180.0, 320.2, 239.7, 1.05).finished(); }
};
struct eucm : Model<omnidso::ExtendedUnifiedCamera> {
  static Params params() { return (Params() << 120.0, 118.0, 320.2, 239.7, 0.6, 1.1).finished(); }
};
struct ds : Model<omnidso::DoubleSphereCamera> {
  static Params params() { return (Params() << 100.0, 99.0, 320.2, 239.7, -0.2, 0.6).finished(); }
};
struct kb4 : Model<omnidso::KannalaBrandtCamera> {
  static Params params() {
    return (Params() << 120.0, 119.0, 320.2, 239.7, 0.01, -0.005, 0.001, 0.0002).finished();
  }
};
struct fov : Model<omnidso::FovCamera> {
  // 90° off-axis at r_d = π/(2ω) ≈ 1.69: ≈ 189 px.
  static Params params() { return (Params() << 112.0, 111.0, 320.2, 239.7, 0.93).finished(); }
};

omnidso::ImageF smoothTexture() {
  omnidso::ImageF image(kWidth, kHeight);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      image(u, v) = static_cast<float>(128.0 + 40.0 * std::sin(0.11 * u + 0.05 * v) +
                                       30.0 * std::cos(0.07 * u - 0.13 * v) +
                                       20.0 * std::sin(0.23 * u + 0.19 * v + 0.4));
    }
  }
  return image;
}

template <typename Tag>
void runPhotometric(benchmark::State& state, DifferentiationMode mode) {
  const omnidso::ImageF target = smoothTexture();
  const omnidso::SE3d host(omnidso::so3Exp(Eigen::Vector3d(0.1, -0.2, 0.3)),
                           Eigen::Vector3d(0.5, -0.2, 0.1));
  const omnidso::SE3d motion(omnidso::so3Exp(Eigen::Vector3d(0.02, -0.03, 0.01)),
                             Eigen::Vector3d(0.08, -0.03, 0.05));
  std::array<double, 7> host_pose, target_pose;
  host.toParameters(host_pose.data());
  (host * motion).toParameters(target_pose.data());
  std::array<double, 2> host_affine{0.1, 3.0}, target_affine{-0.05, -2.0};
  typename Tag::Params intrinsics = Tag::params();

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::vector<double> inverse_distances;
  inverse_distances.reserve(kNumPoints);
  for (int attempt = 0; attempt < 10000 && static_cast<int>(costs.size()) < kNumPoints; ++attempt) {
    PhotometricObservation<kPatternSize> obs;
    obs.target_image = &target;
    obs.host.pixel =
        Eigen::Vector2d(20 + (kWidth - 40) * unit(rng), 20 + (kHeight - 40) * unit(rng));
    for (int o = 0; o < kPatternSize; ++o) {
      obs.host.intensity[o] = 100.0 + 50.0 * unit(rng);
      obs.host.sqrt_weight[o] = 0.8;
    }
    const double d = 0.2 + 0.8 * unit(rng);
    const std::array<const double*, 6> blocks = {
        host_pose.data(),   target_pose.data(),   &d,
        host_affine.data(), target_affine.data(), intrinsics.data()};
    if (Tag::status(obs, blocks.data()) != PhotometricStatus::kValid) continue;
    costs.emplace_back(Tag::make(mode, obs));
    inverse_distances.push_back(d);
  }
  if (costs.size() != static_cast<size_t>(kNumPoints)) {
    state.SkipWithError("could not place the benchmark points");
    return;
  }

  std::array<double, kPatternSize> residuals;
  std::array<double, kPatternSize * 7> j_host, j_target;
  std::array<double, kPatternSize> j_d;
  std::array<double, kPatternSize * 2> j_aff_host, j_aff_target;
  std::array<double, kPatternSize * Tag::Params::RowsAtCompileTime> j_intrinsics;
  std::array<double*, 6> jacobians = {j_host.data(),     j_target.data(),     j_d.data(),
                                      j_aff_host.data(), j_aff_target.data(), j_intrinsics.data()};
  size_t i = 0;
  for (auto _ : state) {
    const std::array<const double*, 6> blocks = {host_pose.data(),      target_pose.data(),
                                                 &inverse_distances[i], host_affine.data(),
                                                 target_affine.data(),  intrinsics.data()};
    const bool ok = costs[i]->Evaluate(blocks.data(), residuals.data(), jacobians.data());
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(residuals.data());
    benchmark::ClobberMemory();
    i = (i + 1) % costs.size();
  }
  state.SetItemsProcessed(state.iterations());
}

template <typename Tag>
void BM_PhotometricResidual_Analytic(benchmark::State& state) {
  runPhotometric<Tag>(state, DifferentiationMode::kAnalytic);
}
template <typename Tag>
void BM_PhotometricResidual_Autodiff(benchmark::State& state) {
  runPhotometric<Tag>(state, DifferentiationMode::kAutodiff);
}

BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, pinhole);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, pinhole);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, ucm);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, ucm);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, eucm);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, eucm);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, ds);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, ds);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, kb4);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, kb4);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Analytic, fov);
BENCHMARK_TEMPLATE(BM_PhotometricResidual_Autodiff, fov);

}  // namespace
