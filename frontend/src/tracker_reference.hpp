#pragma once
// Private to coarse_tracker.cc: the tracker's reference (coarse_tracker.hpp). Per pyramid
// level, finest first: the window's points merged into the level's pixels (mean inverse
// distance; the coarse image averages them too), dilated once with `dilate_reference`, and
// their tracking observations. The observations of the reference dilated once more
// (reference_dilation.hpp) are made on first use: only the retry needs them, and most
// references are never retried on.

#include <Eigen/Core>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <omnidso/cameras/pyramid_scaling.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/reference_dilation.hpp>
#include <omnidso/residuals/tracking_residual.hpp>
#include <optional>
#include <utility>
#include <vector>

namespace omnidso {

class TrackerReference {
 public:
  using LevelObservations = std::vector<std::vector<TrackingObservation<1>>>;
  // A level's points in row order, (v, u) → inverse distance: a flat vector, as a reference
  // is built and dropped with every keyframe and a map's thousands of nodes cost time there.
  using LevelPoints = std::vector<std::pair<std::pair<int, int>, double>>;

  TrackerReference(std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                   const Eigen::Vector2d& affine, const CoarseTrackerOptions& options)
      : pyramid_(std::move(pyramid)), exposure_(exposure), affine_(affine), options_(options) {}

  template <template <typename> class M>
  void build(const M<double>& model, const std::vector<TrackingReferencePoint>& points) {
    const int levels = std::min(options_.num_levels, pyramid_->numLevels());
    observations_.assign(levels, {});
    level_points_.assign(levels, {});
    for (int level = 0; level < levels; ++level) {
      const ImageF& image = pyramid_->level(level);
      std::map<std::pair<int, int>, std::pair<double, int>> cells;  // (v, u) → (Σ d, count)
      for (const TrackingReferencePoint& p : points) {
        const int u = static_cast<int>(std::lround(pixelToLevel(p.pixel.x(), level)));
        const int v = static_cast<int>(std::lround(pixelToLevel(p.pixel.y(), level)));
        if (u < 1 || v < 1 || u >= image.width() - 1 || v >= image.height() - 1) continue;
        auto& cell = cells[{v, u}];
        cell.first += p.inverse_distance;
        ++cell.second;
      }
      LevelPoints& merged = level_points_[level];
      merged.reserve(cells.size());
      for (const auto& [key, acc] : cells) merged.emplace_back(key, acc.first / acc.second);
      if (options_.dilate_reference) merged = dilated(merged, level);
      const M<double> level_model = levelModel(model, level);
      for (const auto& [key, d] : merged) {
        auto obs = makeObservation(level_model, level, key, d);
        if (!obs) continue;
        observations_[level].push_back(*obs);
        if (level > 0) continue;
        finest_pixels_.emplace_back(key.second, key.first);
        finest_inverse_distances_.push_back(d);
      }
    }
  }

  // The reference dilated once more, made on the first call (safe from several threads).
  template <template <typename> class M>
  const LevelObservations& dilatedObservations(const M<double>& model) const {
    std::lock_guard<std::mutex> lock(dilated_mutex_);
    if (dilated_made_) return dilated_observations_;
    dilated_observations_.assign(level_points_.size(), {});
    for (size_t level = 0; level < level_points_.size(); ++level) {
      const int l = static_cast<int>(level);
      const M<double> level_model = levelModel(model, l);
      for (const auto& [key, d] : dilated(level_points_[level], l))
        if (auto obs = makeObservation(level_model, l, key, d))
          dilated_observations_[level].push_back(*obs);
    }
    dilated_made_ = true;
    return dilated_observations_;
  }

  const LevelObservations& observations() const { return observations_; }
  // Level 0's points: pixels and inverse distances (for the flow and the second start).
  const std::vector<Eigen::Vector2d>& finestPixels() const { return finest_pixels_; }
  const std::vector<double>& finestInverseDistances() const { return finest_inverse_distances_; }
  double exposure() const { return exposure_; }
  const Eigen::Vector2d& affine() const { return affine_; }

  template <template <typename> class M>
  static M<double> levelModel(const M<double>& model, int level) {
    typename M<double>::VecN params = model.params();
    scaleIntrinsicsToLevel(params, level);
    return M<double>(params);
  }

 private:
  // One pass of dilation at `level`: the diagonal neighbours on levels 0 and 1, the direct
  // ones from level 2 on (DSO's choice), within the level's content.
  LevelPoints dilated(const LevelPoints& points, int level) const {
    const ImageF& image = pyramid_->level(level);
    const LevelInverseDistances out = dilateInverseDistances(
        LevelInverseDistances(points.begin(), points.end()), image.width(), image.height(),
        level < 2 ? DilationNeighbours::kDiagonal : DilationNeighbours::kDirect,
        pyramid_->content(level));
    return LevelPoints(out.begin(), out.end());
  }

  // The tracking observation of the level pixel `key` = (v, u) at inverse distance d.
  template <template <typename> class M>
  std::optional<TrackingObservation<1>> makeObservation(const M<double>& level_model, int level,
                                                        const std::pair<int, int>& key,
                                                        double d) const {
    const Eigen::Vector2d pixel(key.second, key.first);
    // Weighed in E even with `noise_in_encoding` (photometric_residual.hpp): weighed by
    // the encoding's slope too, the full image of D2 lost its scale (0.02 → 0.9 %) where
    // the window and the initialiser gained (docs/performance.md, "Residuals weighed in
    // the camera's encoding"). A likely reason, not measured: the tracker's distances are
    // held fixed, and their errors shift the target pixel, so its residuals' error grows
    // with ‖∇E‖ (the gradient weight's model) more than with the sensor's noise.
    const HostPatch<1> patch =
        makeHostPatch<1>(pyramid_->level(level), pyramid_->gradients(level), pixel);
    auto obs = makeTrackingObservation<M, 1>(level_model, patch, d);
    if (!obs) return obs;
    obs->host_exposure = exposure_;
    obs->gradient = imageGradient(options_.central_difference_gradients);
    obs->host_a = affine_.x();
    obs->host_b = options_.affine_in_reference_gauge ? 0.0 : affine_.y();
    return obs;
  }

  std::shared_ptr<const ImagePyramid> pyramid_;
  double exposure_;
  Eigen::Vector2d affine_;
  const CoarseTrackerOptions& options_;  // the tracker's, which outlives its reference
  LevelObservations observations_;
  std::vector<LevelPoints> level_points_;  // what observations_ were made from
  std::vector<Eigen::Vector2d> finest_pixels_;
  std::vector<double> finest_inverse_distances_;
  mutable std::mutex dilated_mutex_;
  mutable bool dilated_made_ = false;
  mutable LevelObservations dilated_observations_;
};

}  // namespace omnidso
