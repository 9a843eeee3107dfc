#include <omnidso/backend/inverse_distance_residuals.hpp>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/backend/window_photometric_terms.hpp>
#include <omnidso/cameras/double_sphere.hpp>
#include <omnidso/cameras/extended_unified.hpp>
#include <omnidso/cameras/fov.hpp>
#include <omnidso/cameras/kannala_brandt.hpp>
#include <omnidso/cameras/pinhole.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/cameras/unified.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/residuals/photometric_kernel.hpp>

namespace omnidso {
namespace {

template <template <typename> class Camera>
class TypedInverseDistanceResiduals final : public InverseDistanceResiduals {
  using CameraD = Camera<double>;

 public:
  TypedInverseDistanceResiduals(const Eigen::VectorXd& intrinsics,
                                const HostPatch<kWindowPatternSize>& host, const double* host_pose,
                                const double* host_affine, double host_exposure,
                                const std::vector<InverseDistanceTarget>& targets)
      : camera_(levelIntrinsics(intrinsics)), host_(host) {
    unprojectHostPattern(camera_, host_, false, &bearings_);
    for (const InverseDistanceTarget& t : targets) {
      samplers_.emplace_back(*t.image, WindowObservation{}.interpolation, t.content, t.gradient);
      pairs_.push_back(makePhotometricPair(host_pose, t.pose, host_affine, t.affine,
                                           host_exposure, t.exposure));
    }
  }

  int numTargets() const override { return static_cast<int>(pairs_.size()); }

  bool evaluate(int k, double d, Patch* r, Patch* J_d) const override {
    PatchDerivatives<kWindowPatternSize, CameraD::kNumParams> patch;
    const PhotometricPair& pair = pairs_[static_cast<size_t>(k)];
    if (evaluatePhotometricPatch(camera_, samplers_[static_cast<size_t>(k)], host_, bearings_, pair,
                                 d, r->data(), &patch, false) != PhotometricStatus::kValid)
      return false;
    for (int o = 0; o < kWindowPatternSize; ++o) {
      const Eigen::RowVector3d g = patch.d_r_d_x.row(o);
      (*J_d)[o] = g.dot(pair.t);
    }
    return true;
  }

 private:
  // As the cost function scales them (level 0).
  static typename CameraD::VecN levelIntrinsics(const Eigen::VectorXd& intrinsics) {
    typename CameraD::VecN c = intrinsics;
    scaleIntrinsicsToLevel(c, 0);
    return c;
  }

  CameraD camera_;
  HostPatch<kWindowPatternSize> host_;
  HostBearings<kWindowPatternSize, CameraD::kNumParams> bearings_;
  std::vector<ImageSampler> samplers_;
  std::vector<PhotometricPair> pairs_;
};

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
  std::unique_ptr<InverseDistanceResiduals> makeInverseDistanceResiduals(
      const Eigen::VectorXd& intrinsics, const HostPatch<kWindowPatternSize>& host,
      const double* host_pose, const double* host_affine, double host_exposure,
      const std::vector<InverseDistanceTarget>& targets) const override {
    return std::make_unique<TypedInverseDistanceResiduals<Camera>>(intrinsics, host, host_pose,
                                                                   host_affine, host_exposure,
                                                                   targets);
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
  if (matches<FovCamera>(name)) return std::make_unique<TypedFactory<FovCamera>>();
  throw Error("camera model '" + name +
              "' has no photometric residual kernel (pinhole, ucm, eucm, ds, kb4, fov have); "
              "rectify distorted images to their undistorted model first");
}

}  // namespace omnidso
