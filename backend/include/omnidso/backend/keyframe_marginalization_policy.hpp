#pragma once
// Which keyframes leave the window (paper Sec. V-C, following DSO). Keyframes I_1 … I_n,
// I_1 the newest:
//  a. the two newest keyframes (I_1, I_2) are never marginalised;
//  b. a keyframe whose share of points visible in I_1 drops below 5% is marginalised
//     (a keyframe hosting no points has no share and is left to rule c);
//  c. if more than N_f keyframes remain, the one maximising the distance score
//        s(I_i) = √d(i, 1) · Σ_{j ∈ [3, n] \ {i}} (d(i, j) + ε)⁻¹
//     is marginalised, d the Euclidean distance between keyframe positions. The score is
//     small for keyframes close to the newest one and far from the rest: the window keeps
//     keyframes spread out in space, denser near the camera.

#include <omnidso/core/se3.hpp>
#include <vector>

namespace omnidso {

struct KeyframeSummary {
  int id = 0;
  SE3d T_world_cam;
  int num_points = 0;                   // points hosted by the keyframe
  int num_points_visible_in_newest = 0;  // of those, projecting validly into I_1
};

struct KeyframeMarginalizationOptions {
  int max_keyframes = 7;               // N_f
  double min_visible_fraction = 0.05;  // rule b
  double distance_epsilon = 1e-5;      // ε of rule c (metres, at the map's scale)
  int num_protected_newest = 2;        // rule a
};

// `window` is ordered oldest first (the newest keyframe last). Returns the ids to
// marginalise, in the order the rules chose them.
std::vector<int> selectKeyframesToMarginalize(const std::vector<KeyframeSummary>& window,
                                              const KeyframeMarginalizationOptions& options);

// The distance score of rule c for window[index] among `candidates` (indices into window).
double keyframeDistanceScore(const std::vector<KeyframeSummary>& window, size_t index,
                             const std::vector<size_t>& candidates, double epsilon);

}  // namespace omnidso
