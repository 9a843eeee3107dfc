#pragma once
// When a tracked frame becomes a keyframe (paper Sec. V-C "Keyframe Creation"; DSO Sec. 3.1):
// when the scene changed too much since the newest keyframe,
//   s = w_t · f_t / (w + h) + w_rt · f_rt / (w + h) + w_a · |log(t_j e^{a_j} / (t_i e^{a_i}))| > 1,
// f_t / f_rt the RMS pixel shift of the reference points under the translation alone / the
// full motion (coarse_tracker.hpp), with DSO's weights w_t = 0.04·(640+480),
// w_rt = 0.02·(640+480), w_a = 2 — normalised by the image size w + h, so a 640×480 image
// needs an RMS translational flow of 25 px — or when the tracking error has more than doubled
// since the first frame tracked against this keyframe. The odometry passes the size of the
// image content's box (content_mask.hpp, contentExtent): DSO's frames are filled by content, a
// fisheye's disc may fill 38 % of its frame, and measured against the frame such a lens made
// too few keyframes (docs/performance.md, "A small image circle").

#include <omnidso/frontend/coarse_tracker.hpp>

namespace omnidso {

struct KeyframeDecisionOptions {
  double weight_flow_t = 0.04 * (640 + 480);
  double weight_flow_rt = 0.02 * (640 + 480);
  double weight_affine = 2.0;
  double global_weight = 1.0;       // < 1 makes fewer keyframes, > 1 more
  double rmse_growth_factor = 2.0;
};

struct KeyframeDecision {
  bool make_keyframe = false;
  double score = 0.0;       // s above
  bool rmse_grew = false;
};

// brightness_ratio: t_j e^{a_j} / (t_i e^{a_i}) of the frame relative to the keyframe;
// first_rmse: the error of the first frame tracked against the current keyframe.
KeyframeDecision decideKeyframe(const TrackingResult& tracking, double brightness_ratio,
                                double first_rmse, int width, int height,
                                const KeyframeDecisionOptions& options);

}  // namespace omnidso
