#pragma once
// The scale drift (omnidso/core/scale_drift.hpp) as JSON, shared by `omnidso run`'s summary,
// `omnidso eval --json` and the ablation's result files.

#include <nlohmann/json.hpp>
#include <omnidso/core/scale_drift.hpp>

namespace omnidso::cli {

// Keys: window_m, percent_over_sequence, percent_per_10m, percent_per_minute, min_ratio,
// max_ratio, num_samples; with_samples adds "samples": [[distance_m, time_s, ratio], …].
nlohmann::json scaleDriftJson(const ScaleDrift& drift, bool with_samples = false);

}  // namespace omnidso::cli
