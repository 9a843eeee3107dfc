#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <omnidso/core/error.hpp>
#include <omnidso/core/interpolation.hpp>
#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/residuals/residual_pattern.hpp>
#include <vector>

namespace omnidso {
namespace {


double huberWeight(double r, double k) {
  const double a = std::abs(r);
  return a <= k ? 1.0 : k / a;
}

// ‖·‖_γ of eq. 5 for one residual.
double huberEnergy(double r, double k) {
  const double a = std::abs(r);
  return a <= k ? r * r : k * (2.0 * a - k);
}

// The epipolar curve of one point in one target frame (header comment).
template <typename Model>
class EpipolarCurve {
 public:
  EpipolarCurve(const Model& model, const ImmaturePoint& point, const SE3d& T_target_host)
      : model_(model),
        R_(T_target_host.rotationMatrix()),
        t_(T_target_host.translation()),
        Rb_(R_ * point.bearing),
        R_db_du_(R_ * point.d_bearing_d_uv) {
    const Eigen::Vector3d x_far = Rb_ + point.d_min * t_;
    n_far_ = x_far.norm();
    infinite_near_ = !std::isfinite(point.d_max);
    const Eigen::Vector3d x_near = infinite_near_ ? t_ : Rb_ + point.d_max * t_;
    n_near_ = x_near.norm();
    d_min_ = point.d_min;
    d_max_ = point.d_max;
    p0_ = x_far / n_far_;
    p1_ = x_near / n_near_;
  }

  // A degenerate curve: no baseline (pure rotation) or coinciding ends.
  bool degenerate() const {
    return !(n_far_ > 1e-12) || !(n_near_ > 1e-12) || (p1_ - p0_).norm() < 1e-12;
  }

  // Coefficients of p_L(s) = c_b R b + c_t t.
  void coefficients(double s, double* c_b, double* c_t) const {
    *c_b = (1.0 - s) / n_far_ + (infinite_near_ ? 0.0 : s / n_near_);
    *c_t = (1.0 - s) * d_min_ / n_far_ + (infinite_near_ ? s / n_near_ : s * d_max_ / n_near_);
  }

  double inverseDistance(double s) const {
    double c_b, c_t;
    coefficients(s, &c_b, &c_t);
    return c_b > 0.0 ? c_t / c_b : std::numeric_limits<double>::infinity();
  }

  struct Sample {
    Eigen::Vector2d u;
    Eigen::Vector2d du_ds;
    Eigen::Matrix2d pattern_map;  // J_o
  };

  bool sample(double s, Sample* out) const {
    const Eigen::Vector3d p = (1.0 - s) * p0_ + s * p1_;
    Eigen::Matrix<double, 2, 3> J;
    if (!model_.project(p, out->u, &J)) return false;
    out->du_ds = J * (p1_ - p0_);
    double c_b, c_t;
    coefficients(s, &c_b, &c_t);
    out->pattern_map = J * (c_b * R_db_du_);
    return true;
  }

 private:
  const Model& model_;
  Eigen::Matrix3d R_;
  Eigen::Vector3d t_, Rb_;
  Eigen::Matrix<double, 3, 2> R_db_du_;
  Eigen::Vector3d p0_, p1_;
  double n_far_ = 0, n_near_ = 0, d_min_ = 0, d_max_ = 0;
  bool infinite_near_ = false;
};

struct PatternEnergy {
  double energy = 0.0;
  bool valid = false;
};

// The host pattern's intensities as the target should see them, a I_i[p + o] + b (eq. 5):
// the same for every step of one trace.
using ExpectedIntensities = std::array<double, kImmaturePatternSize>;

ExpectedIntensities expectedIntensities(const ImmaturePoint& point, const AffineTransfer& affine) {
  ExpectedIntensities expected;
  for (int i = 0; i < kImmaturePatternSize; ++i)
    expected[i] = affine.a * point.host_intensity[i] + affine.b;
  return expected;
}

PatternEnergy patternEnergy(const ExpectedIntensities& expected, const ImageF& target,
                            const Eigen::Vector2d& u, const Eigen::Matrix2d& pattern_map,
                            double huber, const Mask* content, int spread) {
  PatternEnergy e;
  for (int i = 0; i < kImmaturePatternSize; ++i) {
    const PatternOffset offset = spreadOffset<kImmaturePatternSize>(i, spread);
    const Eigen::Vector2d o(offset.du, offset.dv);
    const Eigen::Vector2d q = u + pattern_map * o;
    double value;
    if (!sampleBilinear(target, q.x(), q.y(), &value, content)) return e;
    e.energy += huberEnergy(value - expected[i], huber);
  }
  e.valid = true;
  return e;
}

// Value and image gradient at (u, v) from one bilinear cell (sampleBilinear on the image and
// on its two gradient images); false where sampleBilinear of the image is false.
bool sampleWithGradients(const ImageF& image, const ImageGradients& gradients, double u, double v,
                         const Mask* content, double* value, double* gx, double* gy) {
  BilinearCell c;
  if (!bilinearCell(image.width(), image.height(), u, v, &c)) return false;
  if (!cellIsContent(content, c)) return false;
  const double fu = u - static_cast<double>(c.u0);
  const double fv = v - static_cast<double>(c.v0);
  *value = bilinearBlend(image, c, fu, fv);
  *gx = bilinearBlend(gradients.dx, c, fu, fv);
  *gy = bilinearBlend(gradients.dy, c, fu, fv);
  return true;
}

// h = σ + e |c| / a of the header comment, at a sample of the curve; infinite when the
// pattern has no gradient along the curve (the whole curve is then the interval).
template <typename Sample>
double intervalHalfWidthPx(const Eigen::Matrix2d& host_structure, const Sample& sample,
                           const EpipolarSearchOptions& options) {
  const Eigen::Matrix2d& J = sample.pattern_map;  // host pattern offset → target pixels
  const double det = J.determinant();
  if (!(std::abs(det) > 1e-12)) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix2d J_inv = J.inverse();
  const Eigen::Matrix2d G = J_inv.transpose() * host_structure * J_inv;
  const Eigen::Vector2d l = sample.du_ds.normalized();
  const Eigen::Vector2d n(-l.y(), l.x());
  const double a = l.dot(G * l);
  const double c = l.dot(G * n);
  if (!(a > 0.0)) return std::numeric_limits<double>::infinity();
  return options.match_sigma_px + options.curve_offset_px * std::abs(c) / a;
}

template <typename Model>
TraceResult trace(const Model& model, ImmaturePoint& point, const SE3d& T_target_host,
                  const ImageF& target, const ImageGradients& gradients,
                  const AffineTransfer& affine, const EpipolarSearchOptions& options,
                  const Mask* content) {
  TraceResult result;
  const EpipolarCurve<Model> curve(model, point, T_target_host);
  auto finish = [&](TraceStatus status) {
    point.last_status = status;
    result.status = status;
    return result;
  };
  if (curve.degenerate()) return finish(TraceStatus::kSkipped);

  // Walk from the far end, one pixel per step, skipping segments outside the domain. The
  // steps' buffer is kept per thread: a trace runs for every candidate in every frame.
  struct Step {
    double s, path_px, energy;
  };
  thread_local std::vector<Step> steps;
  steps.clear();
  const ExpectedIntensities expected = expectedIntensities(point, affine);
  typename EpipolarCurve<Model>::Sample sample;
  double s = 0.0, path = 0.0;
  int domain_skips = 0;
  const double fallback_step = 1.0 / 256.0;
  double total_curve_px = 0.0;
  while (s <= 1.0 && path <= options.max_search_px) {
    if (!curve.sample(s, &sample)) {
      if (++domain_skips > options.max_domain_skips) break;
      s += fallback_step;
      continue;
    }
    const double speed = sample.du_ds.norm();  // pixels per unit s
    if (!(speed > 1e-9)) break;
    const PatternEnergy e =
        patternEnergy(expected, target, sample.u, sample.pattern_map, options.huber, content,
                      point.pattern_spread);
    if (e.valid) steps.push_back({s, path, e.energy});
    const double ds = 1.0 / speed;
    if (steps.empty() && s == 0.0) total_curve_px = speed;  // first-order length of the curve
    s += ds;
    path += 1.0;
  }
  result.steps = static_cast<int>(steps.size());
  // A curve shorter than the converged length: nothing left to search. As written this
  // fires only when the first step's pattern left the image (total_curve_px is recorded
  // only then); a converged interval is otherwise searched again. Skipping every converged
  // interval before the walk, as DSO does, was measured twice and not kept: D3's crop
  // worse over five seeds (docs/performance.md, "The search's converged intervals").
  if (total_curve_px > 0.0 && total_curve_px < options.converged_px &&
      point.last_status != TraceStatus::kUninitialized)
    return finish(TraceStatus::kSkipped);
  if (steps.empty()) return finish(TraceStatus::kOutOfBounds);

  const auto best_it = std::min_element(steps.begin(), steps.end(),
                                        [](const Step& a, const Step& b) { return a.energy < b.energy; });
  double second = std::numeric_limits<double>::infinity();
  for (const Step& st : steps)
    if (std::abs(st.path_px - best_it->path_px) > options.second_best_radius_px)
      second = std::min(second, st.energy);
  point.quality = second / std::max(best_it->energy, 1e-12);
  if (best_it->energy > options.outlier_energy_per_pixel * kImmaturePatternSize)
    return finish(TraceStatus::kOutlier);

  // Gauss–Newton on s: r_o(s) with ∂r_o/∂s = ∇I_j(u_o) · ∂u_L/∂s, steps clamped to ½ px.
  double s_best = best_it->s;
  for (int it = 0; it < options.gn_iterations; ++it) {
    if (!curve.sample(s_best, &sample)) break;
    double H = 0.0, g = 0.0;
    bool ok = true;
    for (int i = 0; i < kImmaturePatternSize && ok; ++i) {
      const PatternOffset offset = spreadOffset<kImmaturePatternSize>(i, point.pattern_spread);
      const Eigen::Vector2d o(offset.du, offset.dv);
      const Eigen::Vector2d q = sample.u + sample.pattern_map * o;
      double value, gx, gy;
      ok = sampleWithGradients(target, gradients, q.x(), q.y(), content, &value, &gx, &gy);
      if (!ok) break;
      const double r = value - expected[i];
      const double J = gx * sample.du_ds.x() + gy * sample.du_ds.y();
      const double w = huberWeight(r, options.huber);
      H += w * J * J;
      g += w * J * r;
    }
    if (!ok || !(H > 0.0)) break;
    const double max_step = 0.5 / sample.du_ds.norm();
    const double step = std::clamp(-g / H, -max_step, max_step);
    s_best = std::clamp(s_best + step, 0.0, 1.0);
    if (std::abs(step) * sample.du_ds.norm() < 1e-3) break;
  }
  if (!curve.sample(s_best, &sample)) return finish(TraceStatus::kOutOfBounds);
  result.match = sample.u;
  result.energy = best_it->energy;
  if (point.quality < options.min_quality) return finish(TraceStatus::kBadCondition);

  const double half_px = intervalHalfWidthPx(point.host_structure, sample, options);
  const double ds = half_px / sample.du_ds.norm();
  point.d_min = std::max(0.0, curve.inverseDistance(std::max(0.0, s_best - ds)));
  point.d_max = curve.inverseDistance(std::min(1.0, s_best + ds));
  point.last_interval_px = 2.0 * half_px;
  ++point.num_good_traces;
  return finish(TraceStatus::kGood);
}

}  // namespace

const char* toString(TraceStatus status) {
  switch (status) {
    case TraceStatus::kUninitialized: return "uninitialized";
    case TraceStatus::kGood: return "good";
    case TraceStatus::kSkipped: return "skipped";
    case TraceStatus::kOutOfBounds: return "out-of-bounds";
    case TraceStatus::kOutlier: return "outlier";
    case TraceStatus::kBadCondition: return "bad-condition";
  }
  return "unknown";
}

double ImmaturePoint::inverseDistanceEstimate() const {
  if (std::isfinite(d_max)) return 0.5 * (d_min + d_max);
  return d_min;
}

bool makeImmaturePoint(const Camera& camera, const ImageF& host_image,
                       const ImageGradients& host_gradients, int host_id,
                       const Eigen::Vector2d& pixel, ImmaturePoint* point,
                       int pattern_spread) {
  if (pattern_spread < 1)
    throw Error("makeImmaturePoint: the pattern's spread must be >= 1, got " +
                std::to_string(pattern_spread));
  ImmaturePoint p;
  p.host_id = host_id;
  p.pixel = pixel;
  p.pattern_spread = pattern_spread;
  const bool ok = std::visit(
      [&](const auto& model) { return model.unproject(pixel, p.bearing, &p.d_bearing_d_uv); },
      camera.model());
  if (!ok) return false;
  for (int i = 0; i < kImmaturePatternSize; ++i) {
    const PatternOffset offset = spreadOffset<kImmaturePatternSize>(i, pattern_spread);
    const double u = pixel.x() + offset.du;
    const double v = pixel.y() + offset.dv;
    Eigen::Vector2d g;
    if (!sampleWithGradients(host_image, host_gradients, u, v, nullptr, &p.host_intensity[i],
                             &g.x(), &g.y()))
      return false;
    p.host_structure += g * g.transpose();
  }
  *point = p;
  return true;
}

TraceResult traceImmaturePoint(ImmaturePoint& point, const Camera& camera,
                               const SE3d& T_target_host, const ImageF& target,
                               const ImageGradients& target_gradients,
                               const AffineTransfer& affine,
                               const EpipolarSearchOptions& options,
                               const Mask* target_content) {
  return std::visit(
      [&](const auto& model) {
        return trace(model, point, T_target_host, target, target_gradients, affine, options,
                     target_content);
      },
      camera.model());
}

}  // namespace omnidso
