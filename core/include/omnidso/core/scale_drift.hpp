#pragma once
// Scale drift of a monocular trajectory: how the estimate's scale changes along the path.
//
// A global Sim(3) alignment S (scale s) fits one scale to the whole run; a monocular
// odometry whose scale shrinks or grows is then too long at one end and too short at the
// other, which the ATE shows only as one number. The local scale makes it visible:
//
//   σ_k = s · ‖t(E_j) − t(E_k)‖ / ‖t(G_j) − t(G_k)‖,
//
// for every associated pair k, with j the first later pair whose ground-truth path length
// from k reaches the window Δ (metres along the ground truth). A chord shorter than Δ/2
// (the path turned back on itself) says little about scale, and the pair is left out.
// σ = 1 everywhere for a drift-free estimate (up to noise); σ < 1 where the estimate is
// too short.
//
// The trend: a least-squares line log σ_k ≈ α + β ℓ_k over the ground-truth distance
// ℓ_k travelled to pair k (and likewise α' + β' τ_k over time τ_k). Reported as
//   - drift per 10 m:        (e^{10 β} − 1) · 100 %,
//   - drift per minute:      (e^{60 β'} − 1) · 100 %,
//   - over the sequence:     (e^{β L} − 1) · 100 %, L the ground-truth length,
// i.e. the relative change of the scale from the start to the end of the run as the fitted
// line sees it (+ grows, − shrinks). The log makes a halving and a doubling symmetric.
//
// The default window (computeScaleDriftDefaultWindow): a tenth of the ground-truth length, at
// least 0.5 m, halved while fewer than half of the pairs with a window ahead of them give a
// sample. A long hand-held path through one room (60 s, 67 m, in a room a few metres across)
// has few chords of 6.7 m longer than half of that: three samples, bunched together, whose
// line extrapolated to the whole path read +55 % where their local scales spanned 0.804–0.807.

#include <omnidso/core/metrics.hpp>
#include <optional>
#include <vector>

namespace omnidso {

struct LocalScale {
  double distance_m = 0.0;  // ℓ_k: ground-truth path length from the first pair to pair k
  double time_s = 0.0;      // τ_k: time since the first pair
  double ratio = 1.0;       // σ_k
};

struct ScaleDrift {
  double window_m = 0.0;  // Δ
  std::vector<LocalScale> samples;
  double percent_per_10m = 0.0;
  double percent_per_minute = 0.0;
  double percent_over_sequence = 0.0;
  double min_ratio = 1.0, max_ratio = 1.0;  // extremes of σ
  int pairs_with_window = 0;  // pairs k with ground-truth path of at least Δ after them
};

// Where the default window starts: a tenth of the ground-truth length, at least 0.5 m.
double defaultScaleDriftWindow(double gt_length_m);

// Needs at least three samples for the trend; nullopt when the trajectory is too short for
// them at window_m. `result` is an evaluate() result of the same trajectories.
std::optional<ScaleDrift> computeScaleDrift(const Trajectory& gt, const Trajectory& est,
                                            const EvaluationResult& result, double window_m);

// At the default window (above): defaultScaleDriftWindow, halved while fewer than half of
// pairs_with_window give a sample and the half is still at least 0.5 m.
std::optional<ScaleDrift> computeScaleDriftDefaultWindow(const Trajectory& gt,
                                                         const Trajectory& est,
                                                         const EvaluationResult& result);

}  // namespace omnidso
