// keepConsistentDepths (reference_depth_consistency.hpp): the K nearest neighbours of every
// point from a uniform grid of buckets, searched ring by ring until no unvisited bucket can
// hold a nearer point.
#include <omnidso/frontend/reference_depth_consistency.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <omnidso/core/error.hpp>
#include <string>
#include <utility>

namespace omnidso {
namespace {

// Points bucketed by pixel into square cells of side `cell`.
class PixelGrid {
 public:
  PixelGrid(const std::vector<TrackingReferencePoint>& points, int neighbours) {
    min_ = max_ = points.front().pixel;
    for (const auto& p : points) {
      min_ = min_.cwiseMin(p.pixel);
      max_ = max_.cwiseMax(p.pixel);
    }
    // About K/4 points per cell over the points' bounding box: the K nearest then usually lie
    // within two rings, and the rings gather few more candidates than K.
    const Eigen::Vector2d extent = (max_ - min_).cwiseMax(1.0);
    cell_ = std::max(1.0, 0.5 * std::sqrt(extent.x() * extent.y() * neighbours /
                                          static_cast<double>(points.size())));
    cols_ = static_cast<int>(extent.x() / cell_) + 1;
    rows_ = static_cast<int>(extent.y() / cell_) + 1;
    buckets_.resize(static_cast<size_t>(cols_) * rows_);
    for (size_t i = 0; i < points.size(); ++i) {
      const auto [c, r] = cellOf(points[i].pixel);
      buckets_[static_cast<size_t>(r) * cols_ + c].push_back(static_cast<int>(i));
    }
  }

  std::pair<int, int> cellOf(const Eigen::Vector2d& pixel) const {
    const int c = std::clamp(static_cast<int>((pixel.x() - min_.x()) / cell_), 0, cols_ - 1);
    const int r = std::clamp(static_cast<int>((pixel.y() - min_.y()) / cell_), 0, rows_ - 1);
    return {c, r};
  }

  // The K nearest points to point i (not i itself) as (squared distance, index), nearest
  // first, equal distances by index.
  void nearest(const std::vector<TrackingReferencePoint>& points, int i, int k,
               std::vector<std::pair<double, int>>* out) const {
    out->clear();
    const Eigen::Vector2d& x = points[i].pixel;
    const auto [c0, r0] = cellOf(x);
    const int max_ring = std::max(cols_, rows_);
    for (int ring = 0; ring <= max_ring; ++ring) {
      for (int r = r0 - ring; r <= r0 + ring; ++r) {
        if (r < 0 || r >= rows_) continue;
        const bool edge_row = r == r0 - ring || r == r0 + ring;
        for (int c = c0 - ring; c <= c0 + ring; c += (edge_row || ring == 0) ? 1 : 2 * ring) {
          if (c < 0 || c >= cols_) continue;
          for (int j : buckets_[static_cast<size_t>(r) * cols_ + c])
            if (j != i) out->push_back({(points[j].pixel - x).squaredNorm(), j});
        }
      }
      // A point outside the rings searched lies beyond one of the block's sides that the grid
      // continues past, so at least as far as the nearest such side.
      if (static_cast<int>(out->size()) >= k) {
        std::nth_element(out->begin(), out->begin() + (k - 1), out->end());
        const double kth = (*out)[k - 1].first;
        const double outside = distanceOutside(x, c0, r0, ring);
        if (kth < outside * outside) break;
      }
    }
    // The k nearest, ordered (the rings gather more candidates than k; only k are ordered).
    const auto kth_end =
        out->begin() + std::min<std::ptrdiff_t>(k, static_cast<std::ptrdiff_t>(out->size()));
    std::partial_sort(out->begin(), kth_end, out->end());
    out->erase(kth_end, out->end());
  }

 private:
  // The distance from x to the nearest side of the block of cells within `ring` of (c0, r0)
  // beyond which the grid has cells; +∞ when the block covers the grid.
  double distanceOutside(const Eigen::Vector2d& x, int c0, int r0, int ring) const {
    double d = std::numeric_limits<double>::infinity();
    if (c0 - ring > 0) d = std::min(d, x.x() - (min_.x() + (c0 - ring) * cell_));
    if (c0 + ring < cols_ - 1) d = std::min(d, min_.x() + (c0 + ring + 1) * cell_ - x.x());
    if (r0 - ring > 0) d = std::min(d, x.y() - (min_.y() + (r0 - ring) * cell_));
    if (r0 + ring < rows_ - 1) d = std::min(d, min_.y() + (r0 + ring + 1) * cell_ - x.y());
    return d;
  }

  Eigen::Vector2d min_, max_;
  double cell_ = 1.0;
  int cols_ = 1, rows_ = 1;
  std::vector<std::vector<int>> buckets_;
};

// The median of `values` (the mean of the two middle ones for an even count); reorders them.
double median(std::vector<double>& values) {
  const size_t n = values.size(), half = n / 2;
  std::nth_element(values.begin(), values.begin() + half, values.end());
  const double upper = values[half];
  if (n % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + half));
}

}  // namespace

void validate(const ReferenceDepthConsistencyOptions& options) {
  if (options.neighbours < 0)
    throw Error("reference_depths.neighbours must be >= 0 (0 turns the check off; got " +
                std::to_string(options.neighbours) + ")");
  if (!(options.max_log_deviation > 0.0) || !std::isfinite(options.max_log_deviation))
    throw Error("reference_depths.max_log_deviation must be > 0 and finite (got " +
                std::to_string(options.max_log_deviation) + ")");
}

std::vector<TrackingReferencePoint> keepConsistentDepths(
    std::vector<TrackingReferencePoint> points, const ReferenceDepthConsistencyOptions& options) {
  validate(options);
  const int k = options.neighbours;
  if (k == 0 || points.size() < static_cast<size_t>(k) + 1) return points;
  std::vector<double> log_d(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!(points[i].inverse_distance > 0.0))
      throw Error("keepConsistentDepths: an inverse distance is not positive");
    log_d[i] = std::log(points[i].inverse_distance);
  }
  const PixelGrid grid(points, k);
  std::vector<TrackingReferencePoint> kept;
  kept.reserve(points.size());
  std::vector<std::pair<double, int>> near;
  std::vector<double> values;
  for (size_t i = 0; i < points.size(); ++i) {
    grid.nearest(points, static_cast<int>(i), k, &near);
    values.clear();
    for (const auto& [distance, j] : near) values.push_back(log_d[j]);
    if (std::abs(log_d[i] - median(values)) <= options.max_log_deviation)
      kept.push_back(points[i]);
  }
  return kept;
}

}  // namespace omnidso
