#pragma once
// Field-of-view figures of a camera, in degrees. Angles are measured from the optical axis
// (acos of the bearing's z) on each side and added, so that they stay right beyond 180°
// (an angle between two bearings never exceeds 180°, the sum of the two sides can).
//
// Where an image border point is not a valid pixel (outside a fisheye's image circle), the
// boundary of the valid region on the segment from the principal point to that border
// point is used instead; the valid region is taken to be star-shaped around the principal
// point, which holds for the image circle of every model here.

#include <Eigen/Core>

#include "omnidso/cameras/camera.hpp"

namespace omnidso {

struct FieldOfView {
  double horizontal_deg = 0.0;  // left ↔ right border midpoints on the principal-point row
  double vertical_deg = 0.0;    // top ↔ bottom border midpoints on the principal-point column
  double diagonal_deg = 0.0;    // the larger of the two corner-to-corner diagonals
  double maximum_deg = 0.0;     // 2 × largest angle from the axis over all valid pixels
  double valid_pixel_fraction = 0.0;  // of validityMask()
};

double horizontalFovDeg(const Camera& camera);
double verticalFovDeg(const Camera& camera);
double diagonalFovDeg(const Camera& camera);
// Twice the largest angle from the optical axis over the valid pixels: the angles along
// rays from the principal point to every border pixel (stopping at the image circle where
// the border is invalid) — the largest angle is on the boundary of the valid region.
double maximumFovDeg(const Camera& camera);
double validPixelFraction(const Camera& camera);

FieldOfView fieldOfView(const Camera& camera);

// The point where the segment from `inside` (a valid pixel) towards `target` leaves the
// valid region (`target` itself when valid), found by bisection to 1e-6 px.
Eigen::Vector2d lastValidPixelTowards(const Camera& camera, const Eigen::Vector2d& inside,
                                      const Eigen::Vector2d& target);

}  // namespace omnidso
