#pragma once
// The tracking reference's inverse distances checked against their neighbours' before the
// tracker aligns frames to them: a point is kept when
//
//   | ln d_i − median_{j ∈ N_K(i)} ln d_j | ≤ τ,
//
// N_K(i) the K points nearest to point i in the reference keyframe's image (level-0 pixels;
// equal distances broken by the points' order). With fewer than K + 1 points nothing is
// judged and every point is kept.
//
// Why: the tracker takes the reference's inverse distances as known (coarse_tracker.hpp), so
// a point whose inverse distance is wrong pulls the frame's pose towards the motion that
// would fit it. Where a wide view separates a sideways step from a turn by the direction of
// the flow across the image, a narrow view separates them only by parallax — by how the flow
// changes with the points' inverse distances — and wrong ones turn part of the step into
// rotation. Measured against the independent renderer's scene on the 90° pinhole render H12p
// (docs/performance.md, "The tracker's reference against the scene"): 12.5 % of the
// reference points lay more than 10 % off the scene (5 % more than 30 %), wrong from their
// activation on, half of them at a depth edge; their information, residual count or age
// hardly sets them apart. The scene's own inverse distances in the reference, or dropping
// only the points more than 10 % off, bring H12p's six-seed median from 0.098 to 0.060 /
// 0.061 %.
// Neighbours on one surface agree to a few percent: at K = 8, τ = 0.1 this check drops 10 %
// of H12p's reference points, 64 % of them more than 10 % off the scene, and H12p's median
// falls to 0.066 %.
//
// Off by default here (K = 0); `omnidso run` turns it on for views under 115°
// (cli::applyNarrowViewTracking), where it keeps a fast turn's scale (docs/performance.md, "A
// narrow view's tracking reference checked against its neighbours"). On the development set's
// 90° crops it costs (mean of medians 0.077 → 0.087 % over five seeds when first measured,
// D1's crop in four seeds of five; 0.078 → 0.098 % over three in session 50); the full
// image's moved within its seeds' spread (0.0189 → 0.0200 %). Judging a point only where its
// neighbours agree among themselves (so that depth edges keep their points) helped H12p less
// (0.082 %) and D1's crop no better; D1's crop gains nothing even from the scene's own inverse
// distances (its drift is made in the window's solves). Settings `reference_depths.neighbours` (K)
// and `reference_depths.max_log_deviation` (τ).

#include <omnidso/frontend/coarse_tracker.hpp>
#include <vector>

namespace omnidso {

struct ReferenceDepthConsistencyOptions {
  int neighbours = 0;              // K; 0: off (the default, above); 8 for the check
  double max_log_deviation = 0.1;  // τ
};

// Throws omnidso::Error naming the setting unless K ≥ 0 and τ > 0 (finite).
void validate(const ReferenceDepthConsistencyOptions& options);

// The points that pass the check, in their given order (`points` itself, moved, when the
// check is off). Every inverse distance must be > 0.
std::vector<TrackingReferencePoint> keepConsistentDepths(
    std::vector<TrackingReferencePoint> points, const ReferenceDepthConsistencyOptions& options);

}  // namespace omnidso
