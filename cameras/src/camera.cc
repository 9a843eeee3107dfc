#include "omnidso/cameras/camera.hpp"

#include <cmath>
#include <map>
#include <utility>

#include "omnidso/cameras/pyramid_scaling.hpp"
#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

constexpr size_t kNumModels = std::variant_size_v<CameraModelVariant>;

template <size_t... I>
std::vector<std::string> modelNames(std::index_sequence<I...>) {
  return {std::variant_alternative_t<I, CameraModelVariant>::kName...};
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// Builds alternative I from params if its kName matches; the caller checked the count.
template <size_t I = 0>
CameraModelVariant makeModel(const std::string& name, const Eigen::VectorXd& params) {
  if constexpr (I == kNumModels) {
    throw Error("unknown camera model '" + name + "'");
  } else {
    using Model = std::variant_alternative_t<I, CameraModelVariant>;
    if (name != Model::kName) return makeModel<I + 1>(name, params);
    if (params.size() != Model::kNumParams) {
      throw Error("camera model '" + name + "' takes " + std::to_string(Model::kNumParams) +
                  " parameters, got " + std::to_string(params.size()));
    }
    return Model(typename Model::VecN(params));
  }
}

// Range checks of the model-specific parameters (after [fx, fy, cx, cy]); each model's
// header gives the meaning: ξ ≥ 0 (UCM, eq. 2), α ∈ [0, 1] and β > 0 (EUCM), ξ > −1 and
// α ∈ [0, 1] (DS; Kalibr's DS calibrations often have ξ < 0), 0 < ω < π (FOV: the model
// divides by ω, and tan(ω/2) is infinite at π). Distortion coefficients are unconstrained.
void checkModelRanges(const std::string& name, const Eigen::VectorXd& p) {
  const auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw Error("camera model '" + name + "': " + what);
  };
  const auto show = [](double x) { return std::to_string(x); };
  if (name == "ucm" || name == "ucm-radtan") {
    require(p[4] >= 0.0, "xi must be >= 0, got " + show(p[4]));
  } else if (name == "eucm") {
    require(p[4] >= 0.0 && p[4] <= 1.0, "alpha must be in [0, 1], got " + show(p[4]));
    require(p[5] > 0.0, "beta must be > 0, got " + show(p[5]));
  } else if (name == "ds") {
    require(p[4] > -1.0, "xi must be > -1, got " + show(p[4]));
    require(p[5] >= 0.0 && p[5] <= 1.0, "alpha must be in [0, 1], got " + show(p[5]));
  } else if (name == "fov") {
    require(p[4] > 0.0 && p[4] < M_PI,
            "w (the field-of-view parameter omega) must be in (0, pi), got " + show(p[4]));
  }
}

template <typename T>
struct IsDistorted : std::false_type {};
template <typename Base>
struct IsDistorted<DistortedCamera<Base>> : std::true_type {
  using BaseModel = Base;
};

}  // namespace

std::vector<std::string> knownCameraModelNames() {
  return modelNames(std::make_index_sequence<kNumModels>());
}

std::string canonicalCameraModelName(const std::string& name) {
  static const std::map<std::string, std::string> kAliases = {
      {"kb", "kb4"}, {"equidistant", "kb4"}, {"omni", "ucm"}, {"unified", "ucm"},
      {"atan", "fov"}};
  const auto alias = kAliases.find(name);
  if (alias != kAliases.end()) return alias->second;
  const auto names = knownCameraModelNames();
  for (const auto& n : names) {
    if (n == name) return n;
  }
  throw Error("unknown camera model '" + name + "' (known: " + joined(names) +
              "; aliases: kb, equidistant, omni, unified, atan)");
}

Camera::Camera(CameraModelVariant model, int width, int height)
    : model_(std::move(model)), width_(width), height_(height) {}

Camera Camera::create(const std::string& model_name, const Eigen::VectorXd& params, int width,
                      int height) {
  const std::string name = canonicalCameraModelName(model_name);
  CameraModelVariant model = makeModel(name, params);
  for (int i = 0; i < params.size(); ++i) {
    if (!std::isfinite(params[i])) {
      throw Error("camera model '" + name + "': parameter " + std::to_string(i) +
                  " is not a finite number");
    }
  }
  if (!(params[0] > 0.0) || !(params[1] > 0.0)) {
    throw Error("camera model '" + name + "': focal lengths must be positive, got fx = " +
                std::to_string(params[0]) + ", fy = " + std::to_string(params[1]));
  }
  for (int i = 0; i < 4; ++i) {
    if (std::abs(params[i]) > kMaxPixelMagnitude) {
      throw Error("camera model '" + name + "': " + (i < 2 ? "focal length " : "principal point ") +
                  std::to_string(params[i]) + " px is beyond the plausible 1e6 px");
    }
  }
  checkModelRanges(name, params);
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide) {
    throw Error("image size must be in [1, " + std::to_string(kMaxImageSide) + "], got " +
                std::to_string(width) + "x" + std::to_string(height));
  }
  return Camera(std::move(model), width, height);
}

std::string Camera::modelName() const {
  return std::visit([](const auto& m) -> std::string { return m.kName; }, model_);
}

Eigen::VectorXd Camera::params() const {
  return std::visit([](const auto& m) -> Eigen::VectorXd { return m.params(); }, model_);
}

std::vector<std::string> Camera::paramNames() const {
  return std::visit(
      [](const auto& m) {
        return std::vector<std::string>(m.kParamNames.begin(), m.kParamNames.end());
      },
      model_);
}

bool Camera::project(const Eigen::Vector3d& p, Eigen::Vector2d& uv) const {
  const bool in_domain = std::visit([&](const auto& m) { return m.project(p, uv); }, model_);
  return in_domain && inImage(uv);
}

bool Camera::unproject(const Eigen::Vector2d& uv, Eigen::Vector3d& bearing) const {
  return std::visit([&](const auto& m) { return m.unproject(uv, bearing); }, model_);
}

bool Camera::inImage(const Eigen::Vector2d& uv, double border) const {
  return uv.x() >= -0.5 + border && uv.y() >= -0.5 + border && uv.x() < width_ - 0.5 - border &&
         uv.y() < height_ - 0.5 - border;
}

Camera Camera::atPyramidLevel(int level) const {
  CameraModelVariant scaled = model_;
  std::visit([level](auto& m) { scaleIntrinsicsToLevel(m.params(), level); }, scaled);
  return Camera(std::move(scaled), width_ >> level, height_ >> level);
}

bool Camera::hasDistortion() const {
  return std::visit([](const auto& m) { return IsDistorted<std::decay_t<decltype(m)>>::value; },
                    model_);
}

bool Camera::distortsImages() const {
  if (!hasDistortion()) return false;
  const Eigen::VectorXd p = params();
  return (p.tail<4>().array() != 0.0).any();  // [base..., k1, k2, p1, p2]
}

Camera Camera::undistortedModel() const {
  return std::visit(
      [this](const auto& m) -> Camera {
        using Model = std::decay_t<decltype(m)>;
        if constexpr (IsDistorted<Model>::value) {
          using Base = typename IsDistorted<Model>::BaseModel;
          // A distorted model's parameters are [base..., k1, k2, p1, p2].
          const typename Base::VecN base_params = m.params().template head<Base::kNumParams>();
          return Camera(Base(base_params), width_, height_);
        } else {
          return *this;
        }
      },
      model_);
}

bool isValidPixel(const Camera& camera, const Eigen::Vector2d& uv) {
  return camera.inImage(uv) && roundTripsThroughModel(camera, uv);
}

bool roundTripsThroughModel(const Camera& camera, const Eigen::Vector2d& uv) {
  // 1e-3 px: far above the round-trip error of closed-form (≈1e-12 px) and iterative
  // (converged to ≈1e-9 px) unprojections, far below any fold or wrong branch.
  constexpr double kRoundTripTolerancePx = 1e-3;
  Eigen::Vector3d bearing;
  if (!camera.unproject(uv, bearing) || !bearing.allFinite()) return false;
  Eigen::Vector2d back;
  const bool in_domain =
      std::visit([&](const auto& m) { return m.project(bearing, back); }, camera.model());
  return in_domain && (back - uv).norm() < kRoundTripTolerancePx;
}

Mask validityMask(const Camera& camera) {
  Mask mask(camera.width(), camera.height(), 0);
  for (int v = 0; v < camera.height(); ++v) {
    for (int u = 0; u < camera.width(); ++u) {
      mask(u, v) = isValidPixel(camera, Eigen::Vector2d(u, v)) ? 255 : 0;
    }
  }
  return mask;
}

}  // namespace omnidso
