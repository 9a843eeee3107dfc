#include <ceres/ceres.h>

#include <cmath>
#include <numeric>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/residuals/residual_pattern.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>
#include <omnidso/residuals/se3_manifold.hpp>
#include <sstream>

namespace omnidso {
namespace {

// r = √λ (d − d̄): keeps unobservable inverse distances together (header comment).
class InverseDistanceRegularizer final : public ceres::SizedCostFunction<1, 1> {
 public:
  InverseDistanceRegularizer(double sqrt_weight, double mean)
      : sqrt_weight_(sqrt_weight), mean_(mean) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    r[0] = sqrt_weight_ * (x[0][0] - mean_);
    if (J && J[0]) J[0][0] = sqrt_weight_;
    return true;
  }

 private:
  double sqrt_weight_, mean_;
};

}  // namespace

struct Initializer::Impl {
  Camera camera;
  Mask mask;
  InitializerOptions options;
  std::unique_ptr<PhotometricResidualFactory> factory;
  std::shared_ptr<const ImagePyramid> first;
  double first_exposure = 1.0;
  std::vector<Eigen::Vector2d> pixels;
  std::vector<double> inverse_distances;
  std::array<double, 7> pose{};  // T_world_frame with the first frame at the identity
  std::array<double, 2> affine{};
  std::array<double, 7> host_pose{};
  std::array<double, 2> host_affine{};
  Eigen::VectorXd intrinsics;
  SE3Manifold manifold;
  int frames_tried = 0;
  int snapped_at = -1;  // frames_tried when the parallax first sufficed; -1 before
  std::string status = "no frame yet";

  Impl(const Camera& c, const Mask& m, InitializerOptions o)
      : camera(c),
        mask(m),
        options(std::move(o)),
        factory(PhotometricResidualFactory::forModel(c.modelName())),
        intrinsics(c.params()) {}

  void reset() {
    SE3d().toParameters(pose.data());
    SE3d().toParameters(host_pose.data());
    affine = {0.0, 0.0};
    host_affine = {0.0, 0.0};
    frames_tried = 0;
    snapped_at = -1;
  }

  // One level: returns the RMS residual over valid pattern pixels, and the valid mask.
  double solveLevel(int level, const ImagePyramid& frame, double exposure, double lambda,
                    std::vector<bool>* valid_points) {
    const ImageF& host_image = first->level(level);
    const double margin = patternRadius<kWindowPatternSize>() + 1.0;
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    std::unique_ptr<ceres::LossFunction> loss(
        makePhotometricLoss(kWindowPatternSize, options.huber_threshold));
    problem.AddParameterBlock(pose.data(), 7, &manifold);
    problem.AddParameterBlock(host_pose.data(), 7, &manifold);
    problem.SetParameterBlockConstant(host_pose.data());
    problem.AddParameterBlock(host_affine.data(), 2);
    problem.SetParameterBlockConstant(host_affine.data());
    problem.AddParameterBlock(affine.data(), 2);
    problem.AddParameterBlock(intrinsics.data(), static_cast<int>(intrinsics.size()));
    problem.SetParameterBlockConstant(intrinsics.data());
    const double mean_d =
        std::accumulate(inverse_distances.begin(), inverse_distances.end(), 0.0) /
        std::max<size_t>(1, inverse_distances.size());
    std::vector<std::pair<size_t, ceres::ResidualBlockId>> blocks;
    for (size_t i = 0; i < pixels.size(); ++i) {
      const Eigen::Vector2d p(pixelToLevel(pixels[i].x(), level), pixelToLevel(pixels[i].y(), level));
      if (p.x() < margin || p.y() < margin || p.x() > host_image.width() - 1 - margin ||
          p.y() > host_image.height() - 1 - margin)
        continue;
      WindowObservation obs;
      obs.host = makeHostPatch<kWindowPatternSize>(host_image, first->gradients(level), p);
      obs.target_image = &frame.level(level);
      obs.host_exposure = first_exposure;
      obs.target_exposure = exposure;
      obs.level = level;
      double* params[] = {host_pose.data(), pose.data(), &inverse_distances[i],
                          host_affine.data(), affine.data(), intrinsics.data()};
      if (factory->status(obs, params) != PhotometricStatus::kValid) continue;
      blocks.emplace_back(
          i, problem.AddResidualBlock(
                 new OutOfBoundsPenalty(factory->makeCost(DifferentiationMode::kAnalytic, obs),
                                        kDsoOutlierEnergyPerPixel * kWindowPatternSize),
                 loss.get(), std::vector<double*>(params, params + 6)));
      problem.AddResidualBlock(
          new InverseDistanceRegularizer(std::sqrt(lambda), mean_d), nullptr,
          &inverse_distances[i]);
    }
    if (blocks.empty()) return std::numeric_limits<double>::infinity();
    {
      ceres::Solver::Options so;
      auto* ordering = new ceres::ParameterBlockOrdering;
      for (const auto& [i, id] : blocks) ordering->AddElementToGroup(&inverse_distances[i], 0);
      // One group each: Ceres orders a group's blocks by address, which would make the
      // reduced system's column order (and its last bits) depend on the heap layout.
      int group = 1;
      for (double* b : {pose.data(), host_pose.data(), host_affine.data(), affine.data(),
                        intrinsics.data()})
        ordering->AddElementToGroup(b, group++);
      so.linear_solver_ordering.reset(ordering);
      so.linear_solver_type = ceres::DENSE_SCHUR;
      so.max_num_iterations = options.max_iterations_per_level;
      so.logging_type = ceres::SILENT;
      ceres::Solver::Summary summary;
      ceres::Solve(so, &problem, &summary);
    }
    double sum = 0.0;
    int n = 0;
    valid_points->assign(pixels.size(), false);
    for (const auto& [i, id] : blocks) {
      // The wrapped residual's energy; infinite where it is out of bounds or its inverse
      // distance went negative (it only carried the penalty then).
      const double energy = rawEnergy(problem, id);
      if (!std::isfinite(energy)) continue;
      (*valid_points)[i] = true;
      sum += energy;
      n += kWindowPatternSize;
    }
    return n ? std::sqrt(sum / n) : std::numeric_limits<double>::infinity();
  }

  double parallax(const std::vector<bool>& valid) const {
    const SE3d T = SE3d::fromParameters(pose.data());
    double sum = 0.0;
    int n = 0;
    for (size_t i = 0; i < pixels.size(); ++i) {
      if (!valid[i]) continue;
      Eigen::Vector3d b;
      Eigen::Vector2d u;
      // T_world_frame = T_first_frame: the point in the frame is T⁻¹ x; translation only.
      const SE3d T_frame_first = T.inverse();
      if (!camera.unproject(pixels[i], b) ||
          !camera.project(b + inverse_distances[i] * T_frame_first.translation(), u))
        continue;
      sum += (u - pixels[i]).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(sum / n) : 0.0;
  }
};

Initializer::Initializer(const Camera& camera, const Mask& mask, InitializerOptions options)
    : impl_(std::make_unique<Impl>(camera, mask, std::move(options))) {}

Initializer::~Initializer() = default;

bool Initializer::hasFirstFrame() const { return impl_->first != nullptr; }
int Initializer::numFramesTried() const { return impl_->frames_tried; }
const std::string& Initializer::status() const { return impl_->status; }

void Initializer::setFirstFrame(std::shared_ptr<const ImagePyramid> pyramid, double exposure) {
  impl_->first = std::move(pyramid);
  impl_->first_exposure = exposure;
  impl_->reset();
  impl_->pixels.clear();
  impl_->inverse_distances.clear();
  for (const SelectedPixel& p : selectPixels(*impl_->first, impl_->mask, impl_->options.selection)) {
    impl_->pixels.push_back(p.pixel.cast<double>());
    impl_->inverse_distances.push_back(1.0);
  }
  impl_->status = "first frame set with " + std::to_string(impl_->pixels.size()) + " points";
}

InitializationResult Initializer::addFrame(const ImagePyramid& frame, double exposure) {
  InitializationResult result;
  if (!hasFirstFrame()) throw Error("Initializer::addFrame before setFirstFrame");
  ++impl_->frames_tried;
  const int levels = std::min({impl_->options.num_levels, frame.numLevels(),
                               impl_->first->numLevels()});
  const InitializerOptions& o = impl_->options;
  const double min_parallax =
      o.min_parallax_px > 0 ? o.min_parallax_px : 0.01 * (impl_->camera.width() + impl_->camera.height());
  std::vector<bool> valid;
  double rmse = std::numeric_limits<double>::infinity();
  auto solveAllLevels = [&](double lambda) {
    for (int level = levels - 1; level >= 0; --level)
      rmse = impl_->solveLevel(level, frame, exposure, lambda, &valid);
  };
  const bool snapped_before = impl_->snapped_at >= 0;
  solveAllLevels(snapped_before ? o.regularizer_weight : o.pre_snap_regularizer_weight);
  double parallax = impl_->parallax(valid);
  if (!snapped_before && parallax >= min_parallax) {
    impl_->snapped_at = impl_->frames_tried;
    solveAllLevels(o.regularizer_weight);
    parallax = impl_->parallax(valid);
  }
  const int num_valid = static_cast<int>(std::count(valid.begin(), valid.end(), true));
  result.parallax_px = parallax;
  result.rmse = rmse;
  std::ostringstream status;
  status << "after " << impl_->frames_tried << " frames: parallax " << parallax << " px of the "
         << min_parallax << " px needed, photometric error " << rmse << " (at most "
         << impl_->options.max_rmse << "), " << num_valid << " points";
  if (impl_->snapped_at >= 0) status << ", snapped at frame " << impl_->snapped_at;
  impl_->status = status.str();
  if (impl_->snapped_at < 0 || impl_->frames_tried < impl_->snapped_at + o.frames_after_snap ||
      !(parallax >= min_parallax) || !(rmse <= o.max_rmse) || num_valid < o.min_points)
    return result;

  // Scale: mean inverse distance 1 (d' = d/m, t' = m t).
  double mean = 0.0;
  for (size_t i = 0; i < valid.size(); ++i)
    if (valid[i]) mean += impl_->inverse_distances[i];
  mean /= num_valid;
  if (!(mean > 0.0)) return result;
  SE3d T_world_frame = SE3d::fromParameters(impl_->pose.data());
  T_world_frame.translation() *= mean;
  result.T_frame_first = T_world_frame.inverse();
  result.frame_affine = Eigen::Vector2d(impl_->affine[0], impl_->affine[1]);
  for (size_t i = 0; i < valid.size(); ++i) {
    if (!valid[i]) continue;
    result.pixels.push_back(impl_->pixels[i]);
    result.inverse_distances.push_back(impl_->inverse_distances[i] / mean);
  }
  result.done = true;
  return result;
}

}  // namespace omnidso
