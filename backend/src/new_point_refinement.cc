// SlidingWindow::refineNewPoint: the candidate's inverse distance optimised against every
// window keyframe before activation (new_point_refinement.hpp has the equations).
#include <ceres/loss_function.h>

#include <cmath>
#include <limits>
#include <memory>
#include <omnidso/backend/inverse_distance_residuals.hpp>
#include <omnidso/backend/sliding_window.hpp>
#include <vector>

namespace omnidso {
namespace {

// One target's residual at inverse distance d: ρ(‖r‖²), its raw ‖r‖², r and ∂r/∂d.
struct TargetEvaluation {
  bool valid = false;
  double raw_energy = 0.0;
  double robust_energy = 0.0;
  double rho_prime = 0.0;
  Eigen::Matrix<double, kWindowPatternSize, 1> r, J;
};

}  // namespace

NewPointRefinement SlidingWindow::refineNewPoint(int host_id, const Eigen::Vector2d& pixel,
                                                 double inverse_distance,
                                                 const NewPointRefinementOptions& opts) const {
  NewPointRefinement out;
  out.inverse_distance = inverse_distance;
  const WindowKeyframe& host = keyframe(host_id);
  const ImageF& image = host.pyramid->level(0);
  if (!hostPatchFits<kWindowPatternSize>(image, pixel, options_.pattern_spread) ||
      !(inverse_distance > 0.0) || !std::isfinite(inverse_distance)) {
    out.verdict = NewPointVerdict::kInconsistent;
    return out;
  }
  std::vector<InverseDistanceTarget> targets;
  for (const auto& kf : keyframes_) {
    if (kf->id == host_id) continue;
    targets.push_back({&kf->pyramid->level(0), kf->pyramid->content(0), kf->pose.data(),
                       kf->affine.data(), kf->exposure,
                       imageGradient(opts.central_difference_gradients)});
  }
  const std::unique_ptr<InverseDistanceResiduals> residuals = factory_->makeInverseDistanceResiduals(
      intrinsics_,
      makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(0), pixel,
                                        options_.gradient_weight_c, host.pyramid->encodingSlope(0),
                                        options_.pattern_spread),
      host.pose.data(), host.affine.data(), host.exposure, targets);
  out.num_targets = residuals->numTargets();
  double d = inverse_distance;

  auto evaluate = [&](int k) {
    TargetEvaluation e;
    if (!residuals->evaluate(k, d, &e.r, &e.J)) return e;
    e.valid = true;
    e.raw_energy = e.r.squaredNorm();
    double rho[3];
    loss_->Evaluate(e.raw_energy, rho);
    e.robust_energy = rho[0];
    e.rho_prime = rho[1];
    return e;
  };
  const double invalid_energy = options_.outlier_energy_per_pixel * kWindowPatternSize;
  double invalid_rho[3];  // an invalid target costs the outlier energy, as OutOfBoundsPenalty
  loss_->Evaluate(invalid_energy, invalid_rho);
  // The total robust energy at the current d, the Gauss–Newton H and g, and how many targets
  // are good (valid, raw energy within the outlier bound).
  struct Linearization {
    double energy = 0.0, H = 0.0, g = 0.0;
    int num_good = 0;
  };
  auto linearize = [&] {
    Linearization l;
    for (int k = 0; k < residuals->numTargets(); ++k) {
      const TargetEvaluation e = evaluate(k);
      if (!e.valid) {
        l.energy += invalid_rho[0];
        continue;
      }
      l.energy += e.robust_energy;
      l.H += e.rho_prime * e.J.squaredNorm();
      l.g += e.rho_prime * e.J.dot(e.r);
      l.num_good += e.raw_energy <= invalid_energy;
    }
    return l;
  };

  Linearization current = linearize();
  double lambda = 0.1;
  for (int it = 0; it < opts.iterations && current.H > 0.0; ++it) {
    const double step = -current.g / (current.H * (1.0 + lambda));
    const double previous = d;
    d = previous + step;
    Linearization candidate;
    candidate.energy = std::numeric_limits<double>::infinity();
    if (d > 0.0 && std::isfinite(d)) candidate = linearize();
    if (candidate.energy < current.energy) {
      current = candidate;
      lambda *= 0.5;
    } else {
      d = previous;
      lambda *= 5.0;
    }
    if (std::abs(step) < 1e-4 * std::abs(d)) break;
  }
  out.inverse_distance = d;
  out.hessian = current.H;
  out.num_good_residuals = current.num_good;
  const double H = current.H;
  if (!(H >= opts.min_hessian))
    out.verdict = NewPointVerdict::kUnobserved;
  else if (out.num_good_residuals < opts.min_good_residuals || !(d > 0.0) || !std::isfinite(d))
    out.verdict = NewPointVerdict::kInconsistent;
  else
    out.verdict = NewPointVerdict::kAccepted;
  return out;
}

}  // namespace omnidso
