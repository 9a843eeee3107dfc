#pragma once
// Converting a calibration from one camera model to another: least squares (Ceres, autodiff
// through the templated target model) over bearings of the source, sampled on a pixel grid
// across the source's valid image plus points on the boundary of the valid region (the
// fisheye image circle, where models differ most). The residual of a sample is the pixel
// difference between its projection in the target and its source pixel.
//
// The target is initialised from the source's fx fy cx cy, with the focal lengths rescaled so
// that both models agree near the optical axis, and the model-specific parameters started
// from a few standard values (each start is solved; the best result is kept). Converting a
// model to itself starts from the source's own parameters and so reproduces it exactly.
//
// The reported errors are measured on a denser validation grid (plus the boundary), not on
// the samples fitted: rms and max of the pixel distance over the validation bearings the
// target can project. Bearings outside the target's domain (e.g. beyond 90° for a pinhole)
// are counted in `validation_outside_domain` and not in the error figures.

#include <string>
#include <vector>

#include "omnidso/cameras/camera.hpp"

namespace ceres {
class Problem;
}

namespace omnidso {

// A box constraint on one parameter (index in the model's order; ±infinity: none).
struct ParameterBound {
  int index;
  double lower;
  double upper;
};

// The bounds that keep a solver inside Camera::create's ranges: fx, fy > 0 (1e-6), UCM ξ ≥ 0,
// EUCM α ∈ [0, 1] and β > 0, DS ξ > −1 and α ∈ [0, 1], FOV ω ∈ (0, π) (1e-6 inside).
std::vector<ParameterBound> cameraParameterBounds(const std::string& canonical_name);
// Applies `bounds` to the parameter block `params` of `problem`.
void setParameterBounds(ceres::Problem& problem, double* params,
                        const std::vector<ParameterBound>& bounds);

struct FitOptions {
  int samples_per_axis = 40;      // fitting grid: samples along the longer image side
  int validation_per_axis = 120;  // validation grid, denser and offset from the fitting grid
  int boundary_samples = 360;     // rays from the principal point to the valid region's edge
  int max_iterations = 200;
};

struct FitResult {
  Camera camera;  // the fitted target model, same image size as the source
  double rms_error_px = 0.0;
  double max_error_px = 0.0;
  int num_samples = 0;                // bearings fitted
  int num_validation = 0;             // validation bearings (inside and outside the domain)
  int validation_outside_domain = 0;  // validation bearings the target cannot project
};

// Throws omnidso::Error for an unknown target model name (aliases as in Camera::create).
FitResult fitCameraModel(const Camera& source, const std::string& target_model,
                         const FitOptions& options = FitOptions());

// The solution from every start fitCameraModel tries, lowest fitting cost first (the first is
// fitCameraModel's camera). For callers that refine further on other data (calibration),
// where the start that fits the source best need not lead to the best minimum.
std::vector<Camera> fitCameraModelStarts(const Camera& source, const std::string& target_model,
                                         const FitOptions& options = FitOptions());

// The validation pixels of `source` used by fitCameraModel (valid pixels of a grid with
// `per_axis` samples along the longer side, half a step in from the border, plus
// `boundary_samples` points on the boundary of the valid region), so that callers can check
// the reported errors independently.
std::vector<Eigen::Vector2d> fitSamplePixels(const Camera& source, int per_axis,
                                             int boundary_samples);

}  // namespace omnidso
