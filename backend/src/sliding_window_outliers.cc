// SlidingWindow's outlier removal (sliding_window.hpp): after a solve, a residual whose raw
// energy (out_of_bounds_penalty.hpp, without the robust loss) exceeds DSO's bound of
// outlier_energy_per_pixel × pattern size is removed — invalid ones, out of the image, have
// infinite energy — and points left with too few residuals are dropped with their slot.
#include <limits>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/residuals/out_of_bounds_penalty.hpp>

namespace omnidso {

int SlidingWindow::removeResiduals(double max_energy, int min_residuals_per_point) {
  // The last native solve's energies when nothing has changed since (exactly: the same
  // values, the same residuals); otherwise one evaluation per residual.
  std::vector<double> energies;
  if (!solved_energies_.empty() && solved_fingerprint_ == energyFingerprint())
    energies = std::move(solved_energies_);
  solved_energies_.clear();
  solved_fingerprint_.clear();
  int removed = 0;
  size_t k = 0;  // nativeProblem's residual order: points by id, then targets
  std::vector<int> weak_points;
  for (auto& [pid, point] : points_) {
    for (auto it = point->residuals.begin(); it != point->residuals.end(); ++k) {
      // Every photometric block of the window is an OutOfBoundsPenalty (addResidual).
      const double energy = k < energies.size()
                                ? energies[k]
                                : residualEnergy(*point, it->first, it->second);
      if (energy <= max_energy) {
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
  return removeResiduals(std::numeric_limits<double>::max(), 1);
}

int SlidingWindow::removeOutliers() {
  return removeResiduals(options_.outlier_energy_per_pixel * kWindowPatternSize,
                         options_.min_residuals_per_point);
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
