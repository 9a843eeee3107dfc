#pragma once
// The vignette of a dataset that has no vignette.png, estimated from its own frames
// (core/vignette_estimation.hpp) before the odometry runs: `omnidso run` divides it out as it
// would a calibrated one, reports it in summary.json (settings.photometric.vignette_estimate)
// and writes it as OUT/vignette_estimated.png, a vignette.png for later runs.
// `--no-vignette-estimation` assumes none, as before.

#include <nlohmann/json.hpp>
#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/vignette_estimation.hpp>
#include <string>

namespace omnidso::cli {

// Up to `max_pairs` pairs of consecutive frames, spread evenly over the first `num_frames`
// frames, read and corrected by `response` (its inverse response only; its vignette, if any,
// is not applied); `content`: the scene's pixels on the source grid (empty: all); the
// vignette's centre is the principal point, where `source` projects its optical axis.
VignetteEstimate estimateDatasetVignette(const DatasetIndex& index, size_t num_frames,
                                         const Camera& source, const Mask& content,
                                         const PhotometricCalibration& response,
                                         int max_pairs = 150,
                                         const VignetteEstimationOptions& options = {});

nlohmann::json vignetteEstimateJson(const VignetteEstimate& estimate);

// One line for the user: what was estimated (V at ρ = ½, ¾, 1) or why nothing was.
std::string vignetteEstimateNote(const VignetteEstimate& estimate);

}  // namespace omnidso::cli
