// The initialiser's facade (initializer_impl.hpp): a frame's start by the rotation search,
// its levels coarse to fine, the snap, the scale; the parallax; the state-based hooks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "initializer_impl.hpp"

namespace omnidso {

void Initializer::Impl::searchRotationStart(int level, const ImagePyramid& frame, double exposure,
                                            bool snapped, const std::vector<SE3d>& centres) {
  const int half = options.rotation_search_half_width;
  if (half <= 0 || !(options.rotation_search_step_px > 0) || centres.empty()) return;
  const double step = options.rotation_search_step_px * std::ldexp(1.0, level) * radiansPerPixel();
  if (!(step > 0)) return;
  std::vector<SE3d> candidates = {centres.front()};  // first: the prediction wins ties
  for (const SE3d& centre : centres)
    for (int x = -half; x <= half; ++x)
      for (int y = -half; y <= half; ++y)
        for (int z = -half; z <= half; ++z) {
          Eigen::Matrix<double, 6, 1> xi;
          xi << 0, 0, 0, x * step, y * step, z * step;
          candidates.push_back(centre * SE3d::exp(xi));  // turned in the frame
        }
  const std::vector<double> costs =
      candidateCosts(level, frame, exposure, snapped, candidates, /*least_only=*/true);
  size_t best = 0;
  for (size_t k = 1; k < costs.size(); ++k)
    if (costs[k] < costs[best]) best = k;
  candidates[best].toParameters(pose.data());
}


double Initializer::Impl::radiansPerPixel() const {
  const Eigen::Vector2d c(0.5 * (camera.width() - 1), 0.5 * (camera.height() - 1));
  Eigen::Vector3d a, b;
  if (!camera.unproject(c, a) || !camera.unproject(c + Eigen::Vector2d(1.0, 0.0), b)) return 0.0;
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
}


double Initializer::Impl::solveAllLevels(int levels, const ImagePyramid& frame, double exposure,
                                         bool snapped, std::vector<bool>* valid) {
  double rmse = std::numeric_limits<double>::infinity();
  for (int level = levels - 1; level >= 0; --level)
    rmse = solveLevel(level, frame, exposure, snapped, valid).rmse;
  return rmse;
}


// The pre-snap pose reads a narrow view's sideways shift as a turn (the translation is
// penalised before the snap): in the test of this (initializer_test.cc) it was turned 5°
// about x and its translation tilted 23° toward y, and the snap's solve from there stopped
// halfway. The pure translations are the other end of that ambiguity.
double Initializer::Impl::solveAtSnap(int levels, const ImagePyramid& frame, double exposure,
                                      std::vector<bool>* valid) {
  const InitializerState pre_snap{SE3d::fromParameters(pose.data()),
                                  Eigen::Vector2d(affine[0], affine[1]), inverse_distances};
  const double rmse = solveAllLevels(levels, frame, exposure, /*snapped=*/true, valid);
  const double step = pre_snap.T_world_frame.translation().norm();
  // A default above the acceptance bound is a lost alignment: the parallax that triggered the
  // snap is then an artefact, and a start fitted to it has no translation to find — with the
  // rotation search off, a 10° swing was "initialised" so (WaitsWhenNoPointProjectsAnyMore).
  if (!options.snap_translation_starts || !(step > 0) || !(rmse <= maxRmse())) return rmse;
  // Each start is solved on its own state (withState), the default's solution staying put.
  double best_rmse = options.snap_translation_start_gain * rmse;  // what a start must beat
  std::optional<InitializerState> best;
  std::vector<bool> best_valid;
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {1.0, -1.0}) {
      InitializerState start = pre_snap;
      start.T_world_frame = SE3d();
      start.T_world_frame.translation()[axis] = sign * step;
      std::vector<bool> start_valid;
      const double r = withState(&start, [&] {
        return solveAllLevels(levels, frame, exposure, /*snapped=*/true, &start_valid);
      });
      if (r < best_rmse) {
        best_rmse = r;
        best = std::move(start);
        best_valid = std::move(start_valid);
      }
    }
  if (!best) return rmse;
  best->T_world_frame.toParameters(pose.data());
  affine = {best->affine.x(), best->affine.y()};
  inverse_distances = std::move(best->inverse_distances);
  *valid = std::move(best_valid);
  return best_rmse;
}


// Over the valid points, the translation alone (T_world_frame = T_first_frame: the point in
// the frame is T⁻¹ x): the RMS pixel shift |π(b + d t) − p| and the RMS angle ∠(b, b + d t)
// by which it turns the point's ray (InitializerOptions::min_parallax_px, min_parallax_deg).
Initializer::Impl::Parallax Initializer::Impl::parallax(const std::vector<bool>& valid) const {
  const Eigen::Vector3d t = SE3d::fromParameters(pose.data()).inverse().translation();
  double sum_px = 0.0, sum_angle = 0.0;
  int n_px = 0, n_angle = 0;
  for (size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector3d b;
    if (!valid[i] || !camera.unproject(pixels[i], b)) continue;
    const Eigen::Vector3d moved = b + inverse_distances[i] * t;
    const double angle = std::atan2(b.cross(moved).norm(), b.dot(moved));
    sum_angle += angle * angle;
    ++n_angle;
    Eigen::Vector2d u;
    if (!camera.project(moved, u)) continue;
    sum_px += (u - pixels[i]).squaredNorm();
    ++n_px;
  }
  return {n_px ? std::sqrt(sum_px / n_px) : 0.0,
          n_angle ? std::sqrt(sum_angle / n_angle) * 180.0 / M_PI : 0.0};
}


Initializer::Initializer(const Camera& camera, const Mask& mask, InitializerOptions options) {
  if (!(options.max_rmse_growth >= 0.0) || !std::isfinite(options.max_rmse_growth))
    throw Error("Initializer: initializer.max_rmse_growth must be finite and ≥ 0 (got " +
                std::to_string(options.max_rmse_growth) + ")");
  impl_ = std::make_unique<Impl>(camera, mask, std::move(options));
}

Initializer::~Initializer() = default;

bool Initializer::hasFirstFrame() const { return impl_->first != nullptr; }
int Initializer::numFramesTried() const { return impl_->frames_tried; }
const std::string& Initializer::status() const { return impl_->status; }

void Initializer::setTaskPool(TaskPool* pool) { impl_->pool = pool; }

void Initializer::setFirstFrame(std::shared_ptr<const ImagePyramid> pyramid, double exposure) {
  impl_->first = std::move(pyramid);
  impl_->first_exposure = exposure;
  impl_->reset();
  impl_->pixels.clear();
  impl_->inverse_distances.clear();
  impl_->level_patches.clear();  // their host exposure and capacity are the first frame's
  impl_->level_members.clear();
  for (const SelectedPixel& p : selectPixels(*impl_->first, impl_->mask, impl_->options.selection)) {
    impl_->pixels.push_back(p.pixel.cast<double>());
    impl_->inverse_distances.push_back(1.0);
  }
  impl_->status = "first frame set with " + std::to_string(impl_->pixels.size()) + " points";
}

InitializerState Initializer::state() const {
  return {SE3d::fromParameters(impl_->pose.data()),
          Eigen::Vector2d(impl_->affine[0], impl_->affine[1]), impl_->inverse_distances};
}

InitializerLevelSolve Initializer::solveLevel(const ImagePyramid& frame, double exposure,
                                              int level, bool snapped, InitializerState* state) {
  std::vector<bool> valid;
  return impl_->withState(state, [&] {
    return impl_->solveLevel(level, frame, exposure, snapped, &valid);
  });
}

std::vector<double> Initializer::rotationSearchCosts(const ImagePyramid& frame, double exposure,
                                                     int level, bool snapped,
                                                     const InitializerState& state,
                                                     const std::vector<SE3d>& candidates,
                                                     bool least_only) {
  if (candidates.empty()) return {};
  InitializerState copy = state;
  return impl_->withState(&copy, [&] {
    return impl_->candidateCosts(level, frame, exposure, snapped, candidates, least_only);
  });
}

InitializationResult Initializer::addFrame(const ImagePyramid& frame, double exposure) {
  InitializationResult result;
  if (!hasFirstFrame()) throw Error("Initializer::addFrame before setFirstFrame");
  const int frames_tried_before_this = impl_->frames_tried++;
  const int levels = std::min({impl_->options.num_levels, frame.numLevels(),
                               impl_->first->numLevels()});
  const InitializerOptions& o = impl_->options;
  const double min_parallax =
      o.min_parallax_px > 0 ? o.min_parallax_px : 0.01 * (impl_->camera.width() + impl_->camera.height());
  std::vector<bool> valid;
  const bool snapped_before = impl_->snapped_at >= 0;
  {  // start: the rotation search around the constant-velocity prediction and the last pose
    const SE3d last = SE3d::fromParameters(impl_->pose.data());
    const SE3d before = SE3d::fromParameters(impl_->pose_before.data());
    const SE3d predicted = last * (before.inverse() * last);
    last.toParameters(impl_->pose_before.data());
    predicted.toParameters(impl_->pose.data());
    std::vector<SE3d> centres = {predicted};
    if (frames_tried_before_this > 0) centres.push_back(last);  // else both are the identity
    impl_->searchRotationStart(levels - 1, frame, exposure, snapped_before, centres);
  }
  double rmse = impl_->solveAllLevels(levels, frame, exposure, snapped_before, &valid);
  Impl::Parallax parallax = impl_->parallax(valid);
  auto enough = [&] {
    return parallax.px >= min_parallax && parallax.deg >= o.min_parallax_deg;
  };
  if (!snapped_before && parallax.px >= min_parallax && parallax.deg >= snapParallaxDeg(o)) {
    impl_->snapped_at = impl_->frames_tried;
    rmse = impl_->solveAtSnap(levels, frame, exposure, &valid);
    parallax = impl_->parallax(valid);
  } else if (!snapped_before) {
    impl_->pre_snap_rmse = std::min(impl_->pre_snap_rmse, rmse);
  }
  const int num_valid = static_cast<int>(std::count(valid.begin(), valid.end(), true));
  result.parallax_px = parallax.px;
  result.parallax_deg = parallax.deg;
  result.rmse = rmse;
  result.snapped_at = impl_->snapped_at;
  std::ostringstream status;
  status << "after " << impl_->frames_tried << " frames: parallax " << parallax.px << " px of the "
         << min_parallax << " px needed, triangulation angle " << parallax.deg << "° of the "
         << o.min_parallax_deg << "° needed, photometric error " << rmse << " (at most "
         << impl_->maxRmse() << "), " << num_valid << " points";
  if (impl_->snapped_at >= 0) status << ", snapped at frame " << impl_->snapped_at;
  impl_->status = status.str();
  if (impl_->snapped_at < 0 || impl_->frames_tried < impl_->snapped_at + o.frames_after_snap ||
      !enough() || !(rmse <= impl_->maxRmse()) || num_valid < o.min_points)
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
  // The rotation of the last step (pose_before: T_first_previous); its translation, unscaled
  // here, is replaced by the mean step's.
  result.T_frame_previous = result.T_frame_first * SE3d::fromParameters(impl_->pose_before.data());
  result.T_frame_previous.translation() =
      SE3d::exp(result.T_frame_first.log() / impl_->frames_tried).translation();
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
