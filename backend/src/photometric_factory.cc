#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/cameras/double_sphere.hpp>
#include <omnidso/cameras/extended_unified.hpp>
#include <omnidso/cameras/kannala_brandt.hpp>
#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/unified.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

template <template <typename> class Camera>
class TypedFactory final : public PhotometricResidualFactory {
 public:
  const char* modelName() const override { return Camera<double>::kName; }
  int numIntrinsics() const override { return Camera<double>::kNumParams; }
  ceres::CostFunction* makeCost(DifferentiationMode mode,
                                const WindowObservation& observation) const override {
    return makePhotometricCost<Camera, kWindowPatternSize>(mode, observation);
  }
  PhotometricStatus status(const WindowObservation& observation,
                           double const* const* parameters) const override {
    return photometricStatus<Camera, kWindowPatternSize>(observation, parameters);
  }
  std::shared_ptr<WindowPhotometricTerms> makeWindowTerms() const override {
    return makeWindowPhotometricTerms<Camera>();
  }
  bool unproject(const Eigen::VectorXd& intrinsics, const Eigen::Vector2d& pixel,
                 Eigen::Vector3d& bearing) const override {
    const Camera<double> camera(intrinsics);
    return camera.unproject(pixel, bearing);
  }
};

template <template <typename> class Camera>
bool matches(const std::string& name) {
  return name == Camera<double>::kName;
}

}  // namespace

std::unique_ptr<PhotometricResidualFactory> PhotometricResidualFactory::forModel(
    const std::string& name) {
  if (matches<PinholeCamera>(name)) return std::make_unique<TypedFactory<PinholeCamera>>();
  if (matches<UnifiedCamera>(name)) return std::make_unique<TypedFactory<UnifiedCamera>>();
  if (matches<ExtendedUnifiedCamera>(name))
    return std::make_unique<TypedFactory<ExtendedUnifiedCamera>>();
  if (matches<DoubleSphereCamera>(name))
    return std::make_unique<TypedFactory<DoubleSphereCamera>>();
  if (matches<KannalaBrandtCamera>(name))
    return std::make_unique<TypedFactory<KannalaBrandtCamera>>();
  throw Error("camera model '" + name +
              "' has no photometric residual kernel (pinhole, ucm, eucm, ds, kb4 have); "
              "rectify distorted images to their undistorted model first");
}

}  // namespace omnidso
