#pragma once
// Hand-derived photometric residual (paper eq. 5–7; notation in photometric_residual.hpp):
// a ceres::SizedCostFunction over the blocks
//   host pose (7), target pose (7), inverse distance (1), host affine [a, b] (2),
//   target affine (2), intrinsics (the model's N, level-0 values),
// computing the N pattern pixels together: the relative transform, its rotation and the
// camera at the level are formed once per evaluation. The per-pixel computation is
// photometric_kernel.hpp's, shared with the window's native solver (backend/
// window_photometric_terms.hpp), which forms the same Jacobians in the tangent space.
//
// Jacobians per pattern pixel (g = √w · ∇I_j(p') · ∂π/∂x̃, a 1×3 row; poses perturbed on
// the right, T ⊞ δ = T exp(δ), δ = [rho; phi]):
//   host:    T_th ← T_th exp(δ):  ∂x̃/∂rho = d R,   ∂x̃/∂phi = −R [b]×
//   target:  T_th ← exp(−δ) T_th: ∂x̃/∂rho = −d I,  ∂x̃/∂phi = [x̃]×
//   inverse distance:              ∂x̃/∂d = t
//   intrinsics: √w ∇I_j · (∂π/∂c + ∂π/∂x̃ · R · ∂b/∂c) · ∂c_L/∂c_0   (c_L: level-L scaling)
//   affine, with s = t_j e^{a_j} / (t_i e^{a_i}) and h = I_i[p+o] − b_i:
//     ∂r/∂a_i = √w s h, ∂r/∂b_i = √w s, ∂r/∂a_j = −√w s h, ∂r/∂b_j = −√w.
// The pose Jacobians are mapped to the ambient 7-vector with SE3Manifold's P⁺
// (se3_manifold.hpp), so that J_ambient · P = J_local exactly.
//
// Member definitions live in photometric_analytic_impl.hpp and are instantiated once per
// camera model in residuals/src (photometric_cost_MODEL.cc) for pattern sizes 1, 5, 8.

#include <ceres/sized_cost_function.h>

#include "omnidso/residuals/image_sampler.hpp"
#include "omnidso/residuals/photometric_residual.hpp"

namespace omnidso {

template <template <typename> class Camera, int N>
class PhotometricResidualAnalytic
    : public ceres::SizedCostFunction<N, 7, 7, 1, 2, 2, Camera<double>::kNumParams> {
 public:
  static constexpr int kNumIntrinsics = Camera<double>::kNumParams;

  // observation.target_image must outlive the cost function.
  explicit PhotometricResidualAnalytic(const PhotometricObservation<N>& observation);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Evaluate with the reason for failure; Evaluate() is evaluate(...) == kValid. On any
  // status but kValid the outputs are not written (never NaN).
  PhotometricStatus evaluate(double const* const* parameters, double* residuals,
                             double** jacobians) const;

  const PhotometricObservation<N>& observation() const { return observation_; }

 private:
  PhotometricObservation<N> observation_;
  ImageSampler sampler_;
};

}  // namespace omnidso
