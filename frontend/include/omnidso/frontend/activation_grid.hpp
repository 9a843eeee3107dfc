#pragma once
// Where new points may be activated: an occupancy grid over the newest keyframe's image.
//
// The cells are squares of side
//   c = max(2, s · √(A / N_p))    A: the image content's area in pixels, N_p: num_points,
// so that at s = 1 one point per cell spreads N_p points over the content; s < 1 (the
// activation density, activation_density.hpp) packs them closer while the window is short.
// A cell is occupied once a window point or a newly activated one projects into it; a
// candidate is activated only into a free cell (DSO's distance map, Sec. 3.2 of Engel et al.,
// with its distance at the largest).
//
// The grid is the only bound on activation: how many points the window holds elsewhere does
// not matter. A window full of points that cluster in a few cells — on a forward path the far
// points near the focus of expansion, seen from every keyframe — would otherwise hold every
// new point back, and the near ones, which carry the forward translation, leave the image
// before they are activated (docs/performance.md, "Activation bounded by the grid alone").

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace omnidso {

class ActivationGrid {
 public:
  // width × height: the image; content_area: its pixels with content (at least 1 is used);
  // cell_scale: s above (Error unless finite and ≥ 0).
  ActivationGrid(int width, int height, double content_area, int num_points,
                 double cell_scale = 1.0);

  double cellSize() const { return cell_; }
  // False for a pixel outside the image.
  bool contains(const Eigen::Vector2d& u) const;
  // Occupied cells: true outside the image, so nothing is activated there.
  bool occupied(const Eigen::Vector2d& u) const;
  // Marks u's cell; nothing for a pixel outside the image.
  void occupy(const Eigen::Vector2d& u);
  int numOccupied() const { return num_occupied_; }

 private:
  int index(const Eigen::Vector2d& u) const;

  double cell_;
  int cols_, rows_;
  std::vector<std::uint8_t> cells_;
  int num_occupied_ = 0;
};

}  // namespace omnidso
