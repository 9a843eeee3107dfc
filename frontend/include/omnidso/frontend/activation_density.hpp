#pragma once
// How densely activation fills the newest keyframe: the scale s of the activation grid's cell,
//   c = max(2, s · √(A / N_p))                                   (activation_grid.hpp)
// adapted once per keyframe to the window's point count (DSO adapts its activation
// distance to its point count in the same way).
//
// Why: at s = 1 a cell takes one point of the N_p-point density. In a fast turn the newest
// keyframe shares only a strip of its view with the older keyframes, and the points the window
// keeps crowd that strip: the cells there are taken, the rest of the image has no candidate
// yet (the new keyframe's own are selected after activation). On a 90° pinhole path turning
// 100° in 1.5 s (H12p, frames 100–165) the window held 450–800 points of N_p = 2000 for
// three seconds while 2 400–6 000 converged candidates waited for taken cells; the window's
// relative rotations across the turn came out 2 % short, the new points' distances 2–5 % short
// of the map's, and the scale fell by 10 % in the turn (docs/performance.md, "Activation's
// density adapted to the window's points"). Smaller cells let the candidates in the shared
// strip in.
//
// The rule, before activation, with n the window's points (the leaving keyframes' included,
// as DSO counts them):
//   n < shrink_below · N_p  →  s ← max(min_scale, s − step)
//   otherwise               →  s ← min(1, s + step)
// s starts at 1, and again at every new segment. Wherever the window is not short the grid is
// the fixed one (s = 1). H12p's turn holds 0.25–0.33 N_p; the crops' windows hover at
// 0.6–0.8 N_p in ordinary motion, where DSO's 0.66 made s flicker: the full image of the
// development set moved (D3 0.040 → 0.041 %) and own preset D's crop read 0.15 → 0.36 %; at
// 0.5 every full-image run of the development set is bit for bit as before and H12p's gain
// is the same within its seeds' spread. Measured and dropped as well (docs/performance.md):
// - a hold band as DSO's (s kept while 0.66 N_p ≤ n ≤ N_p) kept s at 0.6–0.8 over most of own
//   preset D's crop, whose window holds 0.7–1.0 N_p, and made the own presets' crops worse
//   (D 0.15 → 0.52 %, A's seed 1 0.18 → 1.37 %);
// - n without the leaving keyframes' points: on a MAV path (D3) the oldest keyframe holds most
//   points when it leaves, and s sank to 0 over frames 290–410 while the window held
//   2 200–3 300 points after each activation.

namespace omnidso {

struct ActivationDensityOptions {
  bool adaptive = true;       // false: s stays 1 (the fixed grid)
  double shrink_below = 0.5;   // a window short of points (DSO's bound: 0.66; below)
  double step = 0.2;           // five steps from the full cell to the smallest
  double min_scale = 0.0;      // 0: cells of the grid's 2 px floor
};

// Throws omnidso::Error unless 0 ≤ shrink_below, 0 < step ≤ 1 and 0 ≤ min_scale ≤ 1 (all
// finite).
void validate(const ActivationDensityOptions& options);

class ActivationDensity {
 public:
  explicit ActivationDensity(const ActivationDensityOptions& options = {});

  // The rule above for one keyframe; returns the new scale.
  double update(int window_points, int num_points);
  double scale() const { return scale_; }
  void reset() { scale_ = 1.0; }

 private:
  ActivationDensityOptions options_;
  double scale_ = 1.0;
};

}  // namespace omnidso
