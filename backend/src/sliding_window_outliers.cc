// SlidingWindow's outlier removal (sliding_window.hpp): after a solve, a residual whose raw
// energy (out_of_bounds_penalty.hpp, without the robust loss) exceeds its bound is removed —
// the bound of its host and target keyframes measured from the window's residuals
// (outlier_threshold.hpp), or DSO's fixed outlier_energy_per_pixel × pattern size; invalid
// ones, out of the image, have infinite energy — and points left with too few residuals are
// dropped with their slot.
#include <algorithm>
#include <limits>
#include <map>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

namespace omnidso {

std::vector<double> SlidingWindow::residualEnergies() {
  // The last native solve's energies when nothing has changed since (exactly: the same
  // values, the same residuals); otherwise one evaluation per residual.
  std::vector<double> energies;
  if (!solved_energies_.empty() && solved_fingerprint_ == energyFingerprint())
    energies = std::move(solved_energies_);
  solved_energies_.clear();
  solved_fingerprint_.clear();
  if (!energies.empty()) return energies;
  // Every photometric block of the window is an OutOfBoundsPenalty (addResidual).
  for (auto& [pid, point] : points_)
    for (const auto& [target_id, block] : point->residuals)
      energies.push_back(residualEnergy(*point, target_id, block));
  return energies;
}

template <typename MaxEnergy>
int SlidingWindow::removeResiduals(const std::vector<double>& energies,
                                   const MaxEnergy& max_energy, int min_residuals_per_point) {
  int removed = 0;
  size_t k = 0;  // residualEnergies' order
  std::vector<int> weak_points;
  for (auto& [pid, point] : points_) {
    for (auto it = point->residuals.begin(); it != point->residuals.end(); ++k) {
      if (energies[k] <= max_energy(point->host_id, it->first)) {
        ++it;
        continue;
      }
      removeResidualBlock(it->second);
      it = point->residuals.erase(it);
      ++removed;
    }
    if (static_cast<int>(point->residuals.size()) < min_residuals_per_point)
      weak_points.push_back(pid);
  }
  for (int pid : weak_points) dropPoint(pid);
  all_residuals_valid_ = true;  // every invalid one had infinite energy
  return removed;
}

int SlidingWindow::dropInvalidResiduals() {
  const auto finite = [](int, int) { return std::numeric_limits<double>::max(); };
  return removeResiduals(residualEnergies(), finite, 1);
}

int SlidingWindow::removeOutliers() {
  const std::vector<double> energies = residualEnergies();
  const double fixed_bound = options_.outlier_energy_per_pixel * kWindowPatternSize;
  if (!options_.outlier_threshold.adaptive || keyframes_.empty()) {
    const auto fixed = [fixed_bound](int, int) { return fixed_bound; };
    return removeResiduals(energies, fixed, options_.min_residuals_per_point);
  }
  // The newest keyframe's bound, from the residuals it observes (re-measured at each pass
  // while it is the newest, as DSO does at each linearisation).
  WindowKeyframe& newest = *keyframes_.back();
  std::vector<double> observed;
  size_t k = 0;
  for (const auto& [pid, point] : points_)
    for (const auto& [target_id, block] : point->residuals) {
      if (target_id == newest.id) observed.push_back(energies[k]);
      ++k;
    }
  newest.outlier_energy =
      keyframeOutlierEnergy(observed, kWindowPatternSize, options_.outlier_threshold);
  std::map<int, double> bound_of;
  for (const auto& kf : keyframes_) bound_of[kf->id] = kf->outlier_energy;
  const auto adaptive = [&bound_of, fixed_bound](int host_id, int target_id) {
    const double bound = std::max(bound_of.at(host_id), bound_of.at(target_id));
    return bound > 0.0 ? bound : fixed_bound;
  };
  return removeResiduals(energies, adaptive, options_.min_residuals_per_point);
}

void SlidingWindow::dropPoint(int id) {
  double* block = &pointRef(id).inverse_distance;
  problem_->RemoveParameterBlock(block);
  marginalizer_.forget(block);
  if (id == scale_anchor_point_id_) scale_anchor_point_id_ = -1;
  erasePoint(id);
}

void SlidingWindow::erasePoint(int id) {
  const auto it = points_.find(id);
  inverse_distance_slots_.release(&it->second->inverse_distance);
  points_.erase(it);
}

}  // namespace omnidso
