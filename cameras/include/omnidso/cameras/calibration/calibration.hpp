#pragma once
// Calibrating several camera models from the same chessboard views, for comparison.
//
// 1. Start (initial_estimate.hpp): equidistant camera, focal length by search, board poses
//    from homographies of bearings.
// 2. Reference fit: KB4 adjusted from that start over all corners (board_adjustment.hpp).
// 3. Outliers, decided once on the reference so that every model is compared on the same
//    corners (a poor model must not improve its figures by dropping what it cannot fit):
//    σ̂ = 1.4826 · median |r| over the residual components (the MAD estimate of the noise);
//    a corner is dropped when ‖r‖ > max(corner_sigmas · σ̂, min_outlier_px), then a view
//    when its RMS exceeds max(view_factor · median view RMS, min_outlier_px) or fewer than
//    half of its corners remain. The reference is re-adjusted on what is kept.
// 4. Each model: KB4 is the reference itself; another model is converted from the reference
//    (fitCameraModelStarts: one solution per standard start); Double Sphere also starts at
//    ξ ∈ {−0.6 … 1} with the focal length at the axis, fx / (1 + ξ), held. Each start is
//    refined on the corners with the reference's poses held (30 iterations), and the best
//    one adjusted in full over the kept corners. The screen matters where a model has
//    separate basins that fit nearly equally (Double Sphere's ξ and fx trade off along a
//    curved valley with a second minimum).
// 5. Selection, by the Bayesian information criterion over the m = 2·corners residuals:
//      BIC = m ln(RSS/m) + k ln(m),  k = number of intrinsic parameters
//    (the board poses are the same 6 per view for every model and cancel in comparisons).
//    The lowest BIC wins: one more parameter must lower the RSS by a factor e^(−ln m / m)
//    (≈ 0.25 % for 1600 corners) to pay for itself; an ordinary RMS comparison would always
//    prefer the model with the most parameters.

#include <string>
#include <vector>

#include "omnidso/cameras/calibration/board_adjustment.hpp"
#include "omnidso/cameras/field_of_view.hpp"

namespace omnidso {

struct CalibrationOptions {
  double corner_sigmas = 5.0;
  double view_factor = 3.0;
  double min_outlier_px = 1.0;
  AdjustmentOptions adjustment;
};

struct ModelCalibration {
  BoardAdjustment fit;
  double rms_px = 0.0;               // over the kept corners, √(mean ‖r‖²)
  double max_px = 0.0;
  std::vector<double> view_rms_px{};  // per view; NaN for dropped views
  int num_params = 0;
  double bic = 0.0;
  FieldOfView fov{};
};

struct CalibrationReport {
  CornerSelection selection;
  double outlier_threshold_px = 0.0;   // corner threshold used in step 3
  int dropped_corners = 0;             // in views that were kept
  std::vector<std::string> dropped_views;  // images, with the reason
  std::vector<ModelCalibration> models;    // in the order asked for
  size_t selected = 0;                     // index into models (lowest BIC)
};

// The canonical names of `names` (aliases allowed), checked; throws omnidso::Error naming an
// unknown model and listing the known ones, or for an empty list / a repeated model.
std::vector<std::string> parseModelList(const std::string& comma_separated);

// Throws omnidso::Error when fewer than 4 views remain after outlier removal.
CalibrationReport calibrateModels(const BoardDetections& detections, const BoardSpec& board,
                                  const std::vector<std::string>& models,
                                  const CalibrationOptions& options = CalibrationOptions());

// RMS, maximum and per-view RMS of `fit` over `selection`; BIC for k parameters; FOV.
ModelCalibration summariseFit(BoardAdjustment fit, const CornerSelection& selection);

}  // namespace omnidso
