#include "omnidso/cameras/model_fitting.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "omnidso/cameras/field_of_view.hpp"
#include "omnidso/core/error.hpp"
#include "penalised_projection.hpp"

namespace omnidso {
namespace {

// Pixel residual of one sampled bearing in the target model (autodiff), with the domain
// penalty of penalised_projection.hpp.
template <typename Model>
struct BearingPixelResidual {
  Eigen::Vector3d bearing;
  Eigen::Vector2d pixel;
  double penalty_px;

  template <typename T>
  bool operator()(const T* params, T* residual) const {
    using ModelT = decltype(std::declval<Model>().template cast<T>());
    const ModelT model{typename ModelT::VecN(Eigen::Map<const typename ModelT::VecN>(params))};
    detail::penalisedProjectionResidual(model, Eigen::Matrix<T, 3, 1>(bearing.cast<T>()), pixel,
                                        penalty_px, residual);
    return true;
  }
};

struct Sample {
  Eigen::Vector2d pixel;
  Eigen::Vector3d bearing;
};

std::vector<Sample> bearingSamples(const Camera& source, int per_axis, int boundary) {
  std::vector<Sample> samples;
  for (const Eigen::Vector2d& uv : fitSamplePixels(source, per_axis, boundary)) {
    Eigen::Vector3d b;
    if (source.unproject(uv, b)) samples.push_back({uv, b});
  }
  return samples;
}

// Per target model: starting values of the parameters after [fx, fy, cx, cy], and the bounds
// of cameraParameterBounds.
struct ModelStarts {
  std::vector<std::vector<double>> extras;
  std::vector<ParameterBound> bounds;
};

ModelStarts startsFor(const std::string& name) {
  const std::vector<double> no_distortion{0, 0, 0, 0};
  const std::vector<ParameterBound> bounds = cameraParameterBounds(name);
  if (name == "ucm") return {{{0.0}, {0.5}, {1.0}}, bounds};
  if (name == "ucm-radtan") return {{{0, 0, 0, 0, 0}, {0.5, 0, 0, 0, 0}, {1.0, 0, 0, 0, 0}}, bounds};
  if (name == "eucm") return {{{0.3, 1.0}, {0.5, 1.0}, {0.6, 1.2}}, bounds};
  if (name == "ds") return {{{0.0, 0.5}, {0.0, 0.6}, {0.2, 0.5}}, bounds};
  if (name == "fov") return {{{0.5}, {0.9}, {1.3}}, bounds};  // ω = 0 is no camera
  if (name == "kb4" || name == "pinhole-radtan") return {{no_distortion}, bounds};
  return {{{}}, bounds};
}

// Pixels per radian along +x at the principal point: the focal length as the image sees it
// (UCM's fx, for one, is (1 + ξ) times it).
double axisFocal(const CameraModelVariant& model, double cx) {
  constexpr double kAngle = 1e-4;
  const Eigen::Vector3d ray(std::sin(kAngle), 0.0, std::cos(kAngle));
  Eigen::Vector2d uv;
  const bool ok = std::visit([&](const auto& m) { return m.project(ray, uv); }, model);
  return ok ? (uv.x() - cx) / std::tan(kAngle) : 0.0;
}

double sourceAxisFocal(const Camera& source, int axis) {
  const Eigen::VectorXd p = source.params();
  Eigen::Vector2d uv(p[2], p[3]);
  uv[axis] += 1e-2;
  Eigen::Vector3d b;
  if (!source.unproject(uv, b)) return p[axis];
  return 1e-2 / std::tan(std::acos(std::clamp(b.z(), -1.0, 1.0)));
}

template <typename Model>
double solveFrom(Eigen::VectorXd& params, const std::vector<Sample>& samples,
                 const ModelStarts& starts, double penalty_px, int max_iterations) {
  ceres::Problem problem;
  for (const Sample& s : samples) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BearingPixelResidual<Model>, 2, Model::kNumParams>(
            new BearingPixelResidual<Model>{s.bearing, s.pixel, penalty_px}),
        nullptr, params.data());
  }
  setParameterBounds(problem, params.data(), starts.bounds);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  // Tight tolerances: a model that contains the source must reach ~1e-6 px, not stop early.
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return summary.final_cost;
}

template <typename Model>
std::vector<Eigen::VectorXd> fitParameters(const Camera& source, const std::string& target_name,
                              const std::vector<Sample>& samples, const FitOptions& options) {
  const Eigen::VectorXd src = source.params();
  const double penalty_px = std::hypot(source.width(), source.height());
  const ModelStarts starts = startsFor(target_name);
  std::vector<Eigen::VectorXd> initial;
  if (source.modelName() == target_name) {
    initial.push_back(src);
  } else {
    for (const std::vector<double>& extra : starts.extras) {
      Eigen::VectorXd p(Model::kNumParams);
      p.head<4>() << 1.0, 1.0, 0.0, 0.0;
      for (size_t i = 0; i < extra.size(); ++i) p[4 + static_cast<int>(i)] = extra[i];
      // Scale the focal lengths so that target and source agree near the optical axis.
      const double unit_focal = axisFocal(Model(typename Model::VecN(p)), 0.0);
      if (!(unit_focal > 0.0)) continue;
      p[0] = sourceAxisFocal(source, 0) / unit_focal;
      p[1] = sourceAxisFocal(source, 1) / unit_focal;
      p[2] = src[2];
      p[3] = src[3];
      initial.push_back(p);
    }
  }
  // (cost, parameters) of every start, lowest cost first.
  std::vector<std::pair<double, Eigen::VectorXd>> solved;
  for (Eigen::VectorXd p : initial) {
    const double cost = solveFrom<Model>(p, samples, starts, penalty_px, options.max_iterations);
    if (std::isfinite(cost)) solved.emplace_back(cost, p);
  }
  if (solved.empty()) throw Error("fitting '" + target_name + "': no usable initialisation");
  std::stable_sort(solved.begin(), solved.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::VectorXd> out;
  for (auto& [cost, p] : solved) out.push_back(std::move(p));
  return out;
}

template <size_t I = 0>
std::vector<Eigen::VectorXd> fitByName(const Camera& source, const std::string& name,
                          const std::vector<Sample>& samples, const FitOptions& options) {
  if constexpr (I == std::variant_size_v<CameraModelVariant>) {
    throw Error("unknown camera model '" + name + "'");
  } else {
    using Model = std::variant_alternative_t<I, CameraModelVariant>;
    if (name == Model::kName) return fitParameters<Model>(source, name, samples, options);
    return fitByName<I + 1>(source, name, samples, options);
  }
}

}  // namespace

std::vector<ParameterBound> cameraParameterBounds(const std::string& name) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<ParameterBound> bounds = {{0, 1e-6, kInf}, {1, 1e-6, kInf}};
  if (name == "ucm" || name == "ucm-radtan") bounds.push_back({4, 0.0, kInf});
  if (name == "eucm") {
    bounds.push_back({4, 0.0, 1.0});
    bounds.push_back({5, 1e-6, kInf});
  }
  if (name == "ds") {
    bounds.push_back({4, -1.0 + 1e-6, kInf});
    bounds.push_back({5, 0.0, 1.0});
  }
  if (name == "fov") bounds.push_back({4, 1e-6, M_PI - 1e-6});
  return bounds;
}

void setParameterBounds(ceres::Problem& problem, double* params,
                        const std::vector<ParameterBound>& bounds) {
  for (const ParameterBound& b : bounds) {
    if (std::isfinite(b.lower)) problem.SetParameterLowerBound(params, b.index, b.lower);
    if (std::isfinite(b.upper)) problem.SetParameterUpperBound(params, b.index, b.upper);
  }
}

std::vector<Camera> fitCameraModelStarts(const Camera& source, const std::string& target_model,
                                         const FitOptions& options) {
  const std::string name = canonicalCameraModelName(target_model);
  const std::vector<Sample> samples =
      bearingSamples(source, options.samples_per_axis, options.boundary_samples);
  if (samples.empty()) throw Error("fitting '" + name + "': the source has no valid pixels");
  std::vector<Camera> cameras;
  for (const Eigen::VectorXd& p : fitByName(source, name, samples, options))
    cameras.push_back(Camera::create(name, p, source.width(), source.height()));
  return cameras;
}

std::vector<Eigen::Vector2d> fitSamplePixels(const Camera& source, int per_axis,
                                             int boundary_samples) {
  std::vector<Eigen::Vector2d> pixels;
  const double step =
      static_cast<double>(std::max(source.width(), source.height())) / std::max(per_axis, 1);
  // Grid cells of size `step` tiling the image; samples at the cell centres.
  for (double v = -0.5 + step / 2; v < source.height() - 0.5; v += step) {
    for (double u = -0.5 + step / 2; u < source.width() - 0.5; u += step) {
      const Eigen::Vector2d uv(u, v);
      if (isValidPixel(source, uv)) pixels.push_back(uv);
    }
  }
  const Eigen::VectorXd p = source.params();
  const Eigen::Vector2d centre(p[2], p[3]);
  if (!roundTripsThroughModel(source, centre) || !source.inImage(centre)) return pixels;
  const double reach = 2.0 * std::hypot(source.width(), source.height());
  const Eigen::Vector2d lo(-0.5, -0.5);
  const Eigen::Vector2d hi(source.width() - 0.5, source.height() - 0.5);
  for (int k = 0; k < boundary_samples; ++k) {
    const double phi = 2.0 * M_PI * (k + 0.5) / boundary_samples;
    const Eigen::Vector2d dir(std::cos(phi), std::sin(phi));
    // Where the ray leaves the image rectangle: the smallest positive exit distance.
    double t = reach;
    for (int a = 0; a < 2; ++a) {
      if (dir[a] > 1e-12) t = std::min(t, (hi[a] - centre[a]) / dir[a]);
      if (dir[a] < -1e-12) t = std::min(t, (lo[a] - centre[a]) / dir[a]);
    }
    pixels.push_back(lastValidPixelTowards(source, centre, centre + t * dir));
  }
  return pixels;
}

FitResult fitCameraModel(const Camera& source, const std::string& target_model,
                         const FitOptions& options) {
  const std::string name = canonicalCameraModelName(target_model);
  const std::vector<Sample> samples =
      bearingSamples(source, options.samples_per_axis, options.boundary_samples);
  if (samples.empty()) throw Error("fitting '" + name + "': the source has no valid pixels");
  const Eigen::VectorXd params = fitByName(source, name, samples, options).front();

  FitResult result{Camera::create(name, params, source.width(), source.height())};
  result.num_samples = static_cast<int>(samples.size());
  double sum_sq = 0.0;
  int inside = 0;
  for (const Sample& s :
       bearingSamples(source, options.validation_per_axis, 2 * options.boundary_samples)) {
    ++result.num_validation;
    Eigen::Vector2d uv;
    const bool ok =
        std::visit([&](const auto& m) { return m.project(s.bearing, uv); }, result.camera.model());
    if (!ok || !uv.allFinite()) {
      ++result.validation_outside_domain;
      continue;
    }
    const double e = (uv - s.pixel).norm();
    sum_sq += e * e;
    result.max_error_px = std::max(result.max_error_px, e);
    ++inside;
  }
  result.rms_error_px = inside > 0 ? std::sqrt(sum_sq / inside) : 0.0;
  return result;
}

}  // namespace omnidso
