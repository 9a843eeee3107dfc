#include <omnidso/backend/keyframe_marginalization_policy.hpp>

#include <cmath>
#include <limits>

namespace omnidso {
namespace {

double distance(const KeyframeSummary& a, const KeyframeSummary& b) {
  return (a.T_world_cam.translation() - b.T_world_cam.translation()).norm();
}

}  // namespace

double keyframeDistanceScore(const std::vector<KeyframeSummary>& window, size_t index,
                             const std::vector<size_t>& candidates, double epsilon) {
  const KeyframeSummary& newest = window.back();
  double sum = 0.0;
  for (size_t j : candidates) {
    if (j == index) continue;
    sum += 1.0 / (distance(window[index], window[j]) + epsilon);
  }
  return std::sqrt(distance(window[index], newest)) * sum;
}

std::vector<int> selectKeyframesToMarginalize(const std::vector<KeyframeSummary>& window,
                                              const KeyframeMarginalizationOptions& options) {
  std::vector<int> chosen;
  const size_t n = window.size();
  const size_t protected_count =
      std::min(n, static_cast<size_t>(std::max(options.num_protected_newest, 0)));
  std::vector<size_t> candidates;  // indices not protected and not yet chosen
  for (size_t i = 0; i + protected_count < n; ++i) {
    const KeyframeSummary& kf = window[i];
    const bool too_few_visible =
        kf.num_points > 0 && static_cast<double>(kf.num_points_visible_in_newest) <
                                 options.min_visible_fraction * kf.num_points;
    if (too_few_visible) {
      chosen.push_back(kf.id);
    } else {
      candidates.push_back(i);
    }
  }
  const size_t remaining = n - chosen.size();
  if (remaining > static_cast<size_t>(options.max_keyframes) && !candidates.empty()) {
    size_t best = candidates.front();
    double best_score = -std::numeric_limits<double>::infinity();
    for (size_t i : candidates) {
      const double score = keyframeDistanceScore(window, i, candidates, options.distance_epsilon);
      if (score > best_score) {  // strict: ties keep the older keyframe (deterministic)
        best_score = score;
        best = i;
      }
    }
    chosen.push_back(window[best].id);
  }
  return chosen;
}

}  // namespace omnidso
