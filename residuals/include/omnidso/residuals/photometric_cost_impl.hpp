#pragma once
// Definitions of the photometric-cost factories; included only by the per-model
// instantiation files residuals/src/photometric_cost_MODEL.cc (AutoDiffCostFunction is a
// heavy template, so each model's Jet code is compiled exactly once).

#include <ceres/autodiff_cost_function.h>

#include <array>

#include "omnidso/residuals/photometric_analytic_impl.hpp"
#include "omnidso/residuals/photometric_cost.hpp"
#include "omnidso/residuals/photometric_functor.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
ceres::CostFunction* makePhotometricCost(DifferentiationMode mode,
                                         const PhotometricObservation<N>& observation) {
  if (mode == DifferentiationMode::kAnalytic) {
    return new PhotometricResidualAnalytic<Camera, N>(observation);
  }
  using Functor = PhotometricResidualFunctor<Camera, N>;
  return new ceres::AutoDiffCostFunction<Functor, N, 7, 7, 1, 2, 2, Functor::kNumIntrinsics>(
      new Functor(observation));
}

template <template <typename> class Camera, int N>
PhotometricStatus photometricStatus(const PhotometricObservation<N>& observation,
                                    double const* const* parameters) {
  std::array<double, N> residuals;
  return PhotometricResidualAnalytic<Camera, N>(observation)
      .evaluate(parameters, residuals.data(), nullptr);
}

}  // namespace omnidso
