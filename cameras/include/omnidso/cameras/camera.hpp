#pragma once
// The runtime camera: one of the model templates (on double) selected by name, plus the
// image size. Code that does not care which model it holds (dataset readers, the command
// line, rectification, the odometry's set-up) works with this class; inner loops that do
// care dispatch once with std::visit on model() and run the templated model directly.
//
// Pixel convention (docs/architecture.md): the centre of the top-left pixel is (0, 0), so
// the image covers [−0.5, w−0.5) × [−0.5, h−0.5).

#include <Eigen/Core>
#include <string>
#include <variant>
#include <vector>

#include "omnidso/cameras/distorted.hpp"
#include "omnidso/cameras/double_sphere.hpp"
#include "omnidso/cameras/extended_unified.hpp"
#include "omnidso/cameras/fov.hpp"
#include "omnidso/cameras/kannala_brandt.hpp"
#include "omnidso/cameras/pinhole.hpp"
#include "omnidso/cameras/unified.hpp"
#include "omnidso/core/image.hpp"

namespace omnidso {

using CameraModelVariant =
    std::variant<PinholeCamera<double>, UnifiedCamera<double>, ExtendedUnifiedCamera<double>,
                 DoubleSphereCamera<double>, KannalaBrandtCamera<double>, FovCamera<double>,
                 DistortedCamera<PinholeCamera<double>>, DistortedCamera<UnifiedCamera<double>>>;

// Plausibility limits of calibration files, so that a mistyped number is refused instead of
// overflowing an int or giving a camera that sees nothing: image sides up to 100 000 px
// (no sensor comes near), focal lengths and principal points up to 1e6 px in magnitude
// (a focal length of 1e6 px is a 0.006° field of view on a 100 px image).
constexpr int kMaxImageSide = 100000;
constexpr double kMaxPixelMagnitude = 1e6;

// The kName of every alternative of CameraModelVariant, in variant order.
std::vector<std::string> knownCameraModelNames();

// The canonical kName for a name or one of its aliases ("kb", "equidistant" → "kb4";
// "omni", "unified" → "ucm"; "atan" → "fov"); throws omnidso::Error listing the known names
// otherwise.
std::string canonicalCameraModelName(const std::string& name);

class Camera {
 public:
  Camera(CameraModelVariant model, int width, int height);

  // Builds a model from its name (kName or alias) and parameters in the model's internal
  // order [fx, fy, cx, cy, extra...]. Throws omnidso::Error for an unknown name (listing the
  // known ones), a wrong parameter count, non-finite parameters, non-positive focal lengths,
  // out-of-range model parameters (UCM ξ < 0, DS ξ ≤ −1, α ∉ [0, 1], β ≤ 0, FOV ω ∉ (0, π)),
  // focal lengths
  // or principal points beyond kMaxPixelMagnitude, or an image size outside
  // [1, kMaxImageSide].
  static Camera create(const std::string& model_name, const Eigen::VectorXd& params, int width,
                       int height);

  std::string modelName() const;
  int width() const { return width_; }
  int height() const { return height_; }
  Eigen::VectorXd params() const;
  std::vector<std::string> paramNames() const;
  const CameraModelVariant& model() const { return model_; }

  // True iff p lies in the model's domain and its pixel lies inside the image.
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d& uv) const;
  // Unit bearing of a pixel; false outside the model's image of the sphere. Pixels outside
  // the image are not rejected here (inImage() tells).
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const;
  // uv ∈ [−0.5 + border, w − 0.5 − border) × [−0.5 + border, h − 0.5 − border).
  bool inImage(const Eigen::Vector2d& uv, double border = 0.0) const;

  // The same camera on pyramid level `level` (pyramid_scaling.hpp): image size w/2^L × h/2^L
  // (integer division, as the pyramid builds it).
  Camera atPyramidLevel(int level) const;

  // True for the radial–tangential variants (raw images that rectification undistorts).
  bool hasDistortion() const;
  // True for a radial–tangential variant with a non-zero coefficient: only then do its images
  // differ from undistortedModel()'s (a calibration that writes zeros needs no rectification).
  bool distortsImages() const;
  // The distortion-free base model with the same size (pinhole-radtan → pinhole,
  // ucm-radtan → ucm); a copy of *this when there is no distortion.
  Camera undistortedModel() const;

 private:
  CameraModelVariant model_;
  int width_;
  int height_;
};

// Pixel validity as the odometry needs it: the pixel centre unprojects and the bearing
// re-projects to the same pixel within 1e-3 px. For wide-angle models this gives the
// fisheye image circle; where a distortion polynomial folds over, the round trip fails.
bool isValidPixel(const Camera& camera, const Eigen::Vector2d& uv);
// The round-trip part of isValidPixel alone (no test against the image rectangle).
bool roundTripsThroughModel(const Camera& camera, const Eigen::Vector2d& uv);
Mask validityMask(const Camera& camera);

}  // namespace omnidso
