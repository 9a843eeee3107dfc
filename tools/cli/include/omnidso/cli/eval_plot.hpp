#pragma once
// `omnidso eval --plot FILE.png`: the per-pose ATE over time beside the local scale over time
// (omnidso/core/scale_drift.hpp), one image of two panels, so that a growing error can be
// read against the scale that caused it.

#include <omnidso/core/metrics.hpp>
#include <omnidso/core/scale_drift.hpp>
#include <optional>
#include <string>

namespace omnidso::cli {

// Refuses (omnidso::Error) to overwrite an existing file.
void writeEvaluationPlot(const std::string& path, const Trajectory& gt,
                         const EvaluationResult& result, const std::optional<ScaleDrift>& drift);

}  // namespace omnidso::cli
