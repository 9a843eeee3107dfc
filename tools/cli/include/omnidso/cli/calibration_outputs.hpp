#pragma once
// What `omnidso calibrate` writes: calibration.json, the Markdown comparison of the models,
// and the PNGs (corner coverage, residual vectors per model, per-view RMS).

#include <nlohmann/json.hpp>
#include <omnidso/cameras/calibration/calibration.hpp>
#include <string>

namespace omnidso::cli {

struct CalibrationRun {
  std::string images_dir;
  BoardSpec board;
  BoardDetections detections;
  CalibrationReport report;
  size_t chosen = 0;            // index into report.models
  bool chosen_by_user = false;  // --select, else the lowest BIC
};

// Everything of the run, per model: parameters with standard deviations, RMS, max, per-view
// RMS, BIC, field of view, views and corners used; the dropped views and corners; every
// view's detected corners (pixels, row-major) with the views and corners that were used.
nlohmann::ordered_json calibrationJson(const CalibrationRun& run);

// The side-by-side table of the models, then each model's parameters ± std dev.
std::string comparisonMarkdown(const CalibrationRun& run);

// coverage.png, residuals_<model>.png, view_rms.png in `dir` (which exists).
void writeCalibrationPlots(const std::string& dir, const CalibrationRun& run);

}  // namespace omnidso::cli
