#pragma once
// A radial vignette estimated from the sequence itself, for data without vignette.png.
//
// Why: a vignette left in the images is a static brightness field. Direct alignment explains
// the brightness a point gains or loses as it crosses that field by moving it, so the field
// pulls the motion towards "no motion" — most of all a zoom, which moves every point along the
// field's radial gradient. On a forward path through a 90° pinhole without photometric
// calibration (docs/performance.md, "No photometric calibration: the vignette estimated")
// the odometry lost its scale (10–14 % of the path); with the vignette divided out it held.
//
// The model (Goldman and Chen's radial vignetting; the one Bergmann et al.'s online
// photometric calibration fits): V(x) = exp(g(ρ)), ρ = ‖x − c‖ / R, with c the principal
// point and R the distance from c to the farthest content pixel; g is piecewise linear on
// `num_knots` equal steps of ρ ∈ [0, 1] with g(0) = 0. A scene point tracked from pixel x₁ of
// one frame to x₂ of the next, with intensities I₁ and I₂ (the images as the odometry reads
// them, after G⁻¹ when pcalib.txt is given), obeys
//   log I₂ − log I₁ = e_k + g(ρ₂) − g(ρ₁),
// e_k the pair's exposure and gain change. e_k is eliminated by removing each pair's mean;
// what is left is linear in the knot values and solved by iteratively reweighted least
// squares (Huber, scale from the median absolute residual) with a small second-difference
// smoothness term and a weaker pull towards 0. Points that keep their distance from the
// centre carry no information: when the median track moves less than
// `min_median_radial_motion_px` that way (a camera standing still) there is no estimate and
// V ≡ 1. Beyond the farthest tracked point g is held at its last measured value.
//
// A lens's vignette does not brighten away from its centre (natural cos⁴ fall-off, the
// aperture's and the pixels' vignetting all darken outwards), so a fit that rises outwards by
// more than `max_outward_rise` is no estimate (V ≡ 1): what it measured is not the lens. A
// car-like forward path at 8 m/s and 10 Hz through a 1241 × 376 strip (docs/performance.md,
// "A vignette estimate that brightens outwards") gave a V rising to 1.32× its central value
// at the edge, where the images fall to 0.73: its tracks moved 2 px radially (median), and
// their brightness changes held, beside the vignette's, a part rising outwards that neither
// the intensity box's size (11–81 px) nor keeping only tracks whose neighbours kept their
// spacing removed. Its cause is not known; the rise is what can be checked.
//
// Tracks come from OpenCV's pyramidal Lucas–Kanade, forward and backward. Lucas–Kanade
// assumes constant brightness and meets the vignette's brightness change by shifting the
// track — the same bias as the odometry's — which halved the estimated fall-off on a
// rendered forward path. So the tracks are found on a high-passed log image
// (log I − G_σ ∗ log I), which a smooth multiplicative field and a gain do not change, and
// the intensities are read from the images themselves (box means over `patch_px`).

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <omnidso/core/image.hpp>
#include <string>
#include <vector>

namespace omnidso {

struct VignetteEstimationOptions {
  int num_knots = 12;
  int max_features_per_pair = 400;
  double min_feature_distance_px = 10.0;
  double highpass_sigma_px = 4.0;     // the tracking image's high-pass
  int tracking_window_px = 21;        // Lucas–Kanade's window
  int tracking_levels = 3;
  double max_forward_backward_px = 0.5;  // a track kept only when it returns this close
  // Intensities: box means over patch_px × patch_px. Small boxes read a point darker where
  // the image magnifies the scene more (the log of a mean over less of the scene around a
  // feature is lower on average): on the development set's fisheyes, whose magnification
  // grows outwards, 5 px overstated the fall-off by 3 % at half the radius, 41 px by < 1 %.
  int patch_px = 41;
  // Intensities used, as fractions of the largest value the images can hold (255 for 8 bit,
  // or G⁻¹(255)): black level and noise below, saturation above.
  double min_intensity_fraction = 0.03;
  double max_intensity_fraction = 0.97;
  // λ of λ h̄ Σ_j (g_{j−1} − 2g_j + g_{j+1})², h̄ = tr(AᵀA) / num_knots: the data's mean
  // information per knot.
  double smoothness_weight = 0.01;
  double ridge_weight = 1e-4;         // λ of λ h̄ Σ_j g_j²
  // Fewer: no estimate. The median over the tracks of how far they moved towards or away
  // from the centre; 0 for a camera standing still.
  double min_median_radial_motion_px = 0.2;
  int irls_iterations = 10;
  // The largest V over V at the centre, less 1, beyond which the fit is refused. Every
  // estimate measured so far on renders with a true (outward-falling) vignette rose by at
  // most 2 % anywhere (a hump near the centre); the forward path above, by 32 %.
  double max_outward_rise = 0.05;
  int min_observations = 2000;        // fewer: no estimate (V ≡ 1)
};

struct VignetteEstimate {
  bool valid = false;
  std::string reason;                 // why not, when !valid
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;                // R
  Eigen::VectorXd knots;              // g at ρ = j / num_knots, j = 0 … num_knots (g₀ = 0)
  int num_pairs = 0;
  int num_observations = 0;
  double residual_mad = 0.0;          // median |residual| after the fit (log units)

  // V at normalised radius ρ (ρ > 1 takes g(1)), normalised so that the largest knot is 1.
  double at(double rho) const;
  // V over a width × height image, normalised to a maximum of 1.
  ImageF map(int width, int height) const;
};

class VignetteEstimator {
 public:
  // `content`: where the images hold the scene (empty: everywhere); `centre`: the principal
  // point in pixels.
  VignetteEstimator(int width, int height, const Mask& content, const Eigen::Vector2d& centre,
                    double max_intensity, VignetteEstimationOptions options = {});

  // Tracks `first` into `second` (two frames close in time) and keeps the observations.
  void addPair(const ImageF& first, const ImageF& second);
  int numObservations() const { return static_cast<int>(rows_.size()); }

  VignetteEstimate solve() const;

 private:
  // One observation: the pair it belongs to, the two normalised radii and log I₂ − log I₁.
  struct Row {
    int pair;
    double rho1, rho2, y;
  };
  int width_, height_;
  cv::Mat usable_;  // 255 where a track may start and end
  Eigen::Vector2d centre_;
  double radius_ = 0.0;
  double max_intensity_;
  VignetteEstimationOptions options_;
  std::vector<Row> rows_;
  int num_pairs_ = 0;
};

}  // namespace omnidso
