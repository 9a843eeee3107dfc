#include <algorithm>
#include <cmath>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/activation_grid.hpp>
#include <string>

namespace omnidso {

namespace {
double checkedScale(double cell_scale) {
  if (!std::isfinite(cell_scale) || cell_scale < 0.0)
    throw Error("ActivationGrid: the cell scale must be finite and >= 0, got " +
                std::to_string(cell_scale));
  return cell_scale;
}
}  // namespace

ActivationGrid::ActivationGrid(int width, int height, double content_area, int num_points,
                               double cell_scale)
    : cell_(std::max(2.0, checkedScale(cell_scale) *
                              std::sqrt(std::max(1.0, content_area) / std::max(1, num_points)))),
      cols_(static_cast<int>(std::max(0, width) / cell_) + 1),
      rows_(static_cast<int>(std::max(0, height) / cell_) + 1),
      cells_(static_cast<size_t>(cols_) * rows_, 0) {}

bool ActivationGrid::contains(const Eigen::Vector2d& u) const { return index(u) >= 0; }

bool ActivationGrid::occupied(const Eigen::Vector2d& u) const {
  const int i = index(u);
  return i < 0 || cells_[static_cast<size_t>(i)] != 0;
}

void ActivationGrid::occupy(const Eigen::Vector2d& u) {
  const int i = index(u);
  if (i < 0 || cells_[static_cast<size_t>(i)] != 0) return;
  cells_[static_cast<size_t>(i)] = 1;
  ++num_occupied_;
}

int ActivationGrid::index(const Eigen::Vector2d& u) const {
  if (!(u.x() >= 0.0 && u.y() >= 0.0)) return -1;  // also rejects NaN
  const int col = static_cast<int>(u.x() / cell_);
  const int row = static_cast<int>(u.y() / cell_);
  if (col >= cols_ || row >= rows_) return -1;
  return row * cols_ + col;
}

}  // namespace omnidso
