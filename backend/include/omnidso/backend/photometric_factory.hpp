#pragma once
// Run-time selection of the photometric residual (residuals/photometric_cost.hpp) by camera
// model name: the window is built once per camera, and the residual kernels are templates on
// the model, so this adapter is the one place where a model name becomes a template.
// Models with residual kernels: pinhole, ucm, eucm, ds, kb4, fov. Distorted models
// (pinhole-radtan, ucm-radtan) are rectified to their undistorted model first (paper Sec. III:
// the raw images are undistorted before the unified model is applied).

#include <memory>
#include <omnidso/residuals/photometric_cost.hpp>
#include <string>
#include <vector>

namespace omnidso {

class WindowPhotometricTerms;
class InverseDistanceResiduals;
struct InverseDistanceTarget;

inline constexpr int kWindowPatternSize = 8;  // DSO's pattern (residual_pattern.hpp)
using WindowObservation = PhotometricObservation<kWindowPatternSize>;

class PhotometricResidualFactory {
 public:
  virtual ~PhotometricResidualFactory() = default;
  virtual const char* modelName() const = 0;
  virtual int numIntrinsics() const = 0;
  // Owned by the caller. Parameter blocks: host pose, target pose, inverse distance,
  // host affine, target affine, intrinsics.
  virtual ceres::CostFunction* makeCost(DifferentiationMode mode,
                                        const WindowObservation& observation) const = 0;
  virtual PhotometricStatus status(const WindowObservation& observation,
                                   double const* const* parameters) const = 0;

  // The residuals of this model for the native window solver (window_photometric_terms.hpp).
  virtual std::shared_ptr<WindowPhotometricTerms> makeWindowTerms() const = 0;

  // One host patch's residuals in `targets` as functions of the inverse distance
  // (inverse_distance_residuals.hpp); level 0, the host's pose and affine block at `host_pose`
  // and `host_affine`, the level-0 `intrinsics` (all read now, not kept).
  virtual std::unique_ptr<InverseDistanceResiduals> makeInverseDistanceResiduals(
      const Eigen::VectorXd& intrinsics, const HostPatch<kWindowPatternSize>& host,
      const double* host_pose, const double* host_affine, double host_exposure,
      const std::vector<InverseDistanceTarget>& targets) const = 0;

  // Unit bearing of a level-0 pixel; false outside the model's image of the sphere.
  virtual bool unproject(const Eigen::VectorXd& intrinsics, const Eigen::Vector2d& pixel,
                         Eigen::Vector3d& bearing) const = 0;

  // Throws omnidso::Error naming the model when it has no residual kernel.
  static std::unique_ptr<PhotometricResidualFactory> forModel(const std::string& model_name);
};

}  // namespace omnidso
