#pragma once
// A start for calibration that needs no guess of the lens: an equidistant camera
// (θd = θ, KB4 with k = 0; it describes fisheye and narrow lenses alike to within a few
// percent near the axis) with the principal point at the image centre and one focal length
// f found by search, plus a pose per view.
//
// For a candidate f every corner is unprojected to a unit bearing b. A planar board satisfies
// b ∝ H·(X, Y, 1)ᵀ with H = λ[r1 r2 t] (Zhang 2000, with bearings instead of normalised
// image points, so that rays beyond 90° from the axis pose no problem). H is the null vector
// of the stacked cross products b × (H x) = 0 (DLT, board coordinates centred and scaled);
// λ follows from ‖r1‖ = ‖r2‖ = 1 and the sign from the bearings pointing at the board;
// R = the nearest rotation to [r1 r2 r1×r2]. The candidate f with the smallest median
// reprojection error (over all corners, through the equidistant camera) is kept; the grid is
// 48 values, geometric from 0.05 to 2 image diagonals.

#include <Eigen/Core>
#include <vector>

#include "omnidso/cameras/calibration/board_detection.hpp"
#include "omnidso/cameras/camera.hpp"
#include "omnidso/core/se3.hpp"

namespace omnidso {

// T_camera_board: board point X (board frame) → camera frame.
struct InitialCalibration {
  Camera camera;                        // kb4 with k1..k4 = 0
  std::vector<SE3d> T_camera_board;     // one per view
  double median_error_px = 0.0;
};

// The pose of a board from the bearings of its corners (the homography above); false when
// the view is degenerate (the DLT null space is not one-dimensional).
bool boardPoseFromBearings(const std::vector<Eigen::Vector3d>& board_points,
                           const std::vector<Eigen::Vector3d>& bearings, SE3d& T_camera_board);

// Throws omnidso::Error when no focal length gives a pose for any view.
InitialCalibration initialEquidistantCalibration(const BoardDetections& detections,
                                                 const BoardSpec& board);

}  // namespace omnidso
