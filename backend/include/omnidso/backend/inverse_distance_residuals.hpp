#pragma once
// One point's photometric residuals (eq. 5–7) in several target keyframes as functions of its
// inverse distance d alone, every other block held: what the candidate refinement before
// activation minimises (new_point_refinement.hpp). The host bearings b_o and each target's
// relative pose and brightness transfer are made once; an evaluation is then the residual
// kernel (residuals/photometric_kernel.hpp) and ∂r_o/∂d = g_o · t (photometric_analytic.hpp,
// the inverse-distance column) — the values of the window's cost function, bit for bit (the
// same kernel on the same inputs), without the per-call unprojection, pose composition and
// other Jacobian columns. perf on D1: the refinement through the cost functions took more of
// the run than the window solve (docs/performance.md, "Native point marginalisation; one
// point per coarse pixel in the initialiser").

#include <Eigen/Core>
#include <omnidso/backend/photometric_factory.hpp>
#include <vector>

namespace omnidso {

// A target keyframe as the residual sees it; the pointers are not owned and must outlive the
// residuals made from it.
struct InverseDistanceTarget {
  const ImageF* image = nullptr;  // level 0
  const Mask* content = nullptr;  // or nullptr for the whole image
  const double* pose = nullptr;   // T_world_cam [qx qy qz qw tx ty tz]
  const double* affine = nullptr;  // [a b]
  double exposure = 1.0;
  ImageGradient gradient = ImageGradient::kInterpolant;  // in ∂r/∂d (image_sampler.hpp)
};

class InverseDistanceResiduals {
 public:
  using Patch = Eigen::Matrix<double, kWindowPatternSize, 1>;
  virtual ~InverseDistanceResiduals() = default;
  virtual int numTargets() const = 0;
  // r and ∂r/∂d of target k at d; false where the residual is invalid (the cost function's
  // Evaluate fails: outside the image or the model's domain, d < 0), r and J unwritten then.
  virtual bool evaluate(int k, double d, Patch* r, Patch* J_d) const = 0;
};

}  // namespace omnidso
