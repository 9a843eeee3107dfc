// The radial vignette from tracked points (vignette_estimation.hpp).
#include <omnidso/core/vignette_estimation.hpp>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace omnidso {
namespace {

cv::Mat asMat(const ImageF& image) {
  return cv::Mat(image.height(), image.width(), CV_32F, const_cast<float*>(image.data()));
}

// The tracking image: log I − G_σ ∗ log I, as 8 bit for Lucas–Kanade. A smooth
// multiplicative field and a gain add a nearly constant to log I, which the high-pass
// removes; the scale (40 per log unit, about e^±3 around 128) keeps the texture's contrast.
cv::Mat trackingImage(const ImageF& image, double sigma) {
  cv::Mat log_image;
  cv::log(cv::max(asMat(image), 1e-3f), log_image);
  cv::Mat smooth;
  cv::GaussianBlur(log_image, smooth, cv::Size(0, 0), sigma);
  cv::Mat out;
  cv::Mat(log_image - smooth).convertTo(out, CV_8U, 40.0, 128.0);
  return out;
}

// g is linear between the knots ρ_j = j / K: at ρ (clamped to [0, 1]) it is
// (1 − f) g_j + f g_{j+1}, with the segment j and the fraction f returned here.
struct KnotSegment {
  int j;
  double f;
};
KnotSegment knotSegment(double rho, int num_knots) {
  const double s = std::clamp(rho, 0.0, 1.0) * num_knots;
  const int j = std::min(static_cast<int>(s), num_knots - 1);
  return {j, s - j};
}

// Adds sign × the interpolation weights of g at ρ to a row over g_0 … g_K.
void addHat(double rho, double sign, int num_knots, Eigen::VectorXd* row) {
  const KnotSegment k = knotSegment(rho, num_knots);
  (*row)[k.j] += sign * (1.0 - k.f);
  (*row)[k.j + 1] += sign * k.f;
}

// The element at position n/2 once sorted (the upper median for an even count).
double upperMedian(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2),
                   values.end());
  return values[values.size() / 2];
}

}  // namespace

double VignetteEstimate::at(double rho) const {
  if (!valid) return 1.0;
  const KnotSegment k = knotSegment(rho, static_cast<int>(knots.size()) - 1);
  return std::exp((1.0 - k.f) * knots[k.j] + k.f * knots[k.j + 1] - knots.maxCoeff());
}

ImageF VignetteEstimate::map(int width, int height) const {
  ImageF out(width, height, 1.f);
  if (!valid) return out;
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      out(u, v) = static_cast<float>(at((Eigen::Vector2d(u, v) - centre).norm() / radius));
  return out;
}

VignetteEstimator::VignetteEstimator(int width, int height, const Mask& content,
                                     const Eigen::Vector2d& centre, double max_intensity,
                                     VignetteEstimationOptions options)
    : width_(width), height_(height), centre_(centre),
      max_intensity_(max_intensity), options_(options) {
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      if (content.empty() || content(u, v))
        radius_ = std::max(radius_, (Eigen::Vector2d(u, v) - centre).norm());
  // Where a track may start and end: neither the tracking window, nor the high-pass's reach
  // (3σ), nor the intensity patch may touch the image's border or the surround of its
  // content, whose edge does not move with the scene.
  const int margin = std::max(options_.tracking_window_px / 2 +
                                  static_cast<int>(std::ceil(3 * options_.highpass_sigma_px)),
                              options_.patch_px / 2) + 1;
  cv::Mat inner(height, width, CV_8U, cv::Scalar(0));
  if (width > 2 * margin && height > 2 * margin)
    inner(cv::Rect(margin, margin, width - 2 * margin, height - 2 * margin)).setTo(255);
  if (!content.empty()) {
    const cv::Mat full(height, width, CV_8U, const_cast<std::uint8_t*>(content.data()));
    cv::Mat eroded;
    cv::erode(full, eroded,
              cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * margin + 1, 2 * margin + 1)));
    inner &= (eroded != 0);
  }
  usable_ = inner;
}

void VignetteEstimator::addPair(const ImageF& first, const ImageF& second) {
  const VignetteEstimationOptions& o = options_;
  const cv::Mat a = trackingImage(first, o.highpass_sigma_px);
  const cv::Mat b = trackingImage(second, o.highpass_sigma_px);
  std::vector<cv::Point2f> p0, p1, back;
  cv::goodFeaturesToTrack(a, p0, o.max_features_per_pair, 0.01, o.min_feature_distance_px, usable_);
  if (p0.empty()) return;
  std::vector<uchar> ok1, ok2;
  std::vector<float> err;
  const cv::Size window(o.tracking_window_px, o.tracking_window_px);
  cv::calcOpticalFlowPyrLK(a, b, p0, p1, ok1, err, window, o.tracking_levels);
  cv::calcOpticalFlowPyrLK(b, a, p1, back, ok2, err, window, o.tracking_levels);

  cv::Mat mean_a, mean_b;
  cv::blur(asMat(first), mean_a, cv::Size(o.patch_px, o.patch_px));
  cv::blur(asMat(second), mean_b, cv::Size(o.patch_px, o.patch_px));
  const double lo = o.min_intensity_fraction * max_intensity_;
  const double hi = o.max_intensity_fraction * max_intensity_;
  auto inside = [&](const cv::Point2f& p) {
    const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
    return u >= 0 && v >= 0 && u < width_ && v < height_ && usable_.at<uchar>(v, u) != 0;
  };
  auto sample = [](const cv::Mat& image, const cv::Point2f& p) {
    cv::Mat patch;
    cv::getRectSubPix(image, cv::Size(1, 1), p, patch, CV_32F);
    return static_cast<double>(patch.at<float>(0, 0));
  };
  const size_t before = rows_.size();
  for (size_t i = 0; i < p0.size(); ++i) {
    if (!ok1[i] || !ok2[i] || cv::norm(back[i] - p0[i]) > o.max_forward_backward_px) continue;
    if (!inside(p0[i]) || !inside(p1[i])) continue;
    const double i1 = sample(mean_a, p0[i]), i2 = sample(mean_b, p1[i]);
    if (!(i1 > lo && i1 < hi && i2 > lo && i2 < hi)) continue;
    rows_.push_back({num_pairs_,
                     (Eigen::Vector2d(p0[i].x, p0[i].y) - centre_).norm() / radius_,
                     (Eigen::Vector2d(p1[i].x, p1[i].y) - centre_).norm() / radius_,
                     std::log(i2) - std::log(i1)});
  }
  if (rows_.size() > before) ++num_pairs_;
}

VignetteEstimate VignetteEstimator::solve() const {
  const VignetteEstimationOptions& o = options_;
  const int k = o.num_knots;
  VignetteEstimate est;
  est.centre = centre_;
  est.radius = radius_;
  est.num_pairs = num_pairs_;
  est.num_observations = numObservations();
  if (est.num_observations < o.min_observations || !(radius_ > 0.0)) {
    est.reason = std::to_string(est.num_observations) + " tracked points, " +
                 std::to_string(o.min_observations) + " needed";
    return est;
  }
  // Points that keep their radius say nothing about V: a camera standing still, or turning
  // about its axis.
  std::vector<double> radial(rows_.size());
  for (size_t i = 0; i < rows_.size(); ++i)
    radial[i] = std::abs(rows_[i].rho2 - rows_[i].rho1) * radius_;
  const double median_radial_px = upperMedian(std::move(radial));
  if (median_radial_px < o.min_median_radial_motion_px) {
    std::ostringstream reason;
    reason << "the points hardly moved towards or away from the centre (median "
           << std::setprecision(2) << median_radial_px << " px, " << o.min_median_radial_motion_px
           << " px needed)";
    est.reason = reason.str();
    return est;
  }
  // Rows a_i · g = y_i over the unknowns g_1 … g_K (g_0 = 0), each pair's mean removed.
  const int n = est.num_observations;
  Eigen::MatrixXd A(n, k);
  Eigen::VectorXd y(n);
  for (size_t start = 0; start < rows_.size();) {
    size_t end = start;
    while (end < rows_.size() && rows_[end].pair == rows_[start].pair) ++end;
    const auto count = static_cast<Eigen::Index>(end - start);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(count, k + 1);  // over g_0 … g_K
    Eigen::VectorXd block_y(count);
    for (size_t i = start; i < end; ++i) {
      Eigen::VectorXd row = Eigen::VectorXd::Zero(k + 1);
      addHat(rows_[i].rho2, 1.0, k, &row);
      addHat(rows_[i].rho1, -1.0, k, &row);
      block.row(static_cast<Eigen::Index>(i - start)) = row.transpose();
      block_y[static_cast<Eigen::Index>(i - start)] = rows_[i].y;
    }
    block.rowwise() -= block.colwise().mean();
    block_y.array() -= block_y.mean();
    A.middleRows(static_cast<Eigen::Index>(start), count) = block.rightCols(k);
    y.segment(static_cast<Eigen::Index>(start), count) = block_y;
    start = end;
  }
  // Second differences over g_0 … g_K (g_0 = 0 fixed): rows j = 1 … K−1 of the unknowns.
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(k - 1, k);
  for (int j = 1; j < k; ++j) {
    if (j - 2 >= 0) D(j - 1, j - 2) += 1.0;  // g_{j−1} (g_0 is not an unknown)
    D(j - 1, j - 1) -= 2.0;
    D(j - 1, j) += 1.0;
  }
  // Both terms are scaled by the data's mean information per knot, h̄ = tr(AᵀA) / K, so that
  // they stay tie-breakers however far the points move: with weights fixed per observation
  // the slow radial motion of a forward path gave them the upper hand and tilted the curve.
  // The pull towards 0 keeps knots that no point crosses (near the centre) defined.
  const double mean_information = (A.transpose() * A).trace() / k;
  const Eigen::MatrixXd prior =
      mean_information * (o.smoothness_weight * D.transpose() * D +
                          o.ridge_weight * Eigen::MatrixXd::Identity(k, k));
  Eigen::VectorXd weights = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(k);
  for (int it = 0; it < o.irls_iterations; ++it) {
    const Eigen::MatrixXd H = A.transpose() * weights.asDiagonal() * A + prior;
    g = H.ldlt().solve(A.transpose() * weights.cwiseProduct(y));
    const Eigen::VectorXd r = (y - A * g).cwiseAbs();
    est.residual_mad = upperMedian(std::vector<double>(r.data(), r.data() + n));
    const double threshold = 1.345 * 1.4826 * std::max(est.residual_mad, 1e-9);
    for (int i = 0; i < n; ++i) weights[i] = r[i] <= threshold ? 1.0 : threshold / r[i];
  }
  est.knots = Eigen::VectorXd::Zero(k + 1);
  est.knots.tail(k) = g;
  // Beyond the farthest tracked point g is not measured, only extrapolated by the smoothness
  // term, which continues the slope; hold it at the last measured knot instead.
  double rho_max = 0.0;
  for (const Row& row : rows_) rho_max = std::max({rho_max, row.rho1, row.rho2});
  const int last = std::min(k, static_cast<int>(std::ceil(rho_max * k)));
  for (int j = last + 1; j <= k; ++j) est.knots[j] = est.knots[last];
  if (!est.knots.allFinite()) {
    est.reason = "the fit did not converge";
    return est;
  }
  // g_0 = 0: the centre's value. A rise outwards beyond the tolerance is not a lens's.
  Eigen::Index peak = 0;
  const double rise = std::exp(est.knots.maxCoeff(&peak)) - 1.0;
  if (rise > o.max_outward_rise) {
    std::ostringstream reason;
    reason << std::fixed << std::setprecision(2) << "the fit brightens away from the centre, to "
           << 1.0 + rise << "× its central value at ρ = " << static_cast<double>(peak) / k
           << ", which no lens's vignette does (" << 1.0 + o.max_outward_rise
           << "× at most is taken for noise)";
    est.reason = reason.str();
    return est;
  }
  est.valid = true;
  return est;
}

}  // namespace omnidso
