// SlidingWindow::refineNewPoint: the candidate's inverse distance optimised against every
// window keyframe before activation (new_point_refinement.hpp has the equations).
#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <cmath>
#include <memory>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/residuals/residual_pattern.hpp>
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

struct Target {
  std::unique_ptr<ceres::CostFunction> cost;
  std::vector<double*> blocks;
};

}  // namespace

NewPointRefinement SlidingWindow::refineNewPoint(int host_id, const Eigen::Vector2d& pixel,
                                                 double inverse_distance,
                                                 const NewPointRefinementOptions& opts) const {
  NewPointRefinement out;
  out.inverse_distance = inverse_distance;
  const WindowKeyframe& host = keyframe(host_id);
  const ImageF& image = host.pyramid->level(0);
  const double margin = patternRadius<kWindowPatternSize>() + 1.0;
  if (!(pixel.x() >= margin && pixel.y() >= margin && pixel.x() <= image.width() - 1 - margin &&
        pixel.y() <= image.height() - 1 - margin) ||
      !(inverse_distance > 0.0) || !std::isfinite(inverse_distance)) {
    out.verdict = NewPointVerdict::kInconsistent;
    return out;
  }
  WindowObservation obs;
  obs.host = makeHostPatch<kWindowPatternSize>(image, host.pyramid->gradients(0), pixel,
                                               options_.gradient_weight_c);
  obs.host_exposure = host.exposure;
  double d = inverse_distance;
  std::vector<Target> targets;
  for (const auto& kf : keyframes_) {
    if (kf->id == host_id) continue;
    obs.target_image = &kf->pyramid->level(0);
    obs.target_exposure = kf->exposure;
    Target t;
    t.cost.reset(factory_->makeCost(DifferentiationMode::kAnalytic, obs));
    // The cost functions only read the blocks; the window's blocks are not modified.
    t.blocks = {const_cast<double*>(host.pose.data()), const_cast<double*>(kf->pose.data()), &d,
                const_cast<double*>(host.affine.data()), const_cast<double*>(kf->affine.data()),
                const_cast<double*>(intrinsics_.data())};
    targets.push_back(std::move(t));
  }
  out.num_targets = static_cast<int>(targets.size());

  auto evaluate = [&](const Target& t, bool with_jacobian) {
    TargetEvaluation e;
    double* jacobians[6] = {nullptr, nullptr, with_jacobian ? e.J.data() : nullptr,
                            nullptr, nullptr, nullptr};
    if (!t.cost->Evaluate(t.blocks.data(), e.r.data(), with_jacobian ? jacobians : nullptr))
      return e;
    e.valid = true;
    e.raw_energy = e.r.squaredNorm();
    double rho[3];
    loss_->Evaluate(e.raw_energy, rho);
    e.robust_energy = rho[0];
    e.rho_prime = rho[1];
    return e;
  };
  const double invalid_energy = options_.outlier_energy_per_pixel * kWindowPatternSize;
  // Total robust energy at the current d, and the Gauss–Newton H and g. An invalid target
  // costs the outlier energy (as OutOfBoundsPenalty does in the window).
  auto linearize = [&](double* energy, double* H, double* g) {
    *energy = *H = *g = 0.0;
    for (const Target& t : targets) {
      const TargetEvaluation e = evaluate(t, H != nullptr);
      if (!e.valid) {
        double rho[3];
        loss_->Evaluate(invalid_energy, rho);
        *energy += rho[0];
        continue;
      }
      *energy += e.robust_energy;
      if (H) {
        *H += e.rho_prime * e.J.squaredNorm();
        *g += e.rho_prime * e.J.dot(e.r);
      }
    }
  };

  double energy, H, g;
  linearize(&energy, &H, &g);
  double lambda = 0.1;
  for (int it = 0; it < opts.iterations && H > 0.0; ++it) {
    const double step = -g / (H * (1.0 + lambda));
    const double previous = d;
    d = previous + step;
    double new_energy, new_H, new_g;
    if (d > 0.0 && std::isfinite(d)) {
      linearize(&new_energy, &new_H, &new_g);
    } else {
      new_energy = std::numeric_limits<double>::infinity();
    }
    if (new_energy < energy) {
      energy = new_energy;
      H = new_H;
      g = new_g;
      lambda *= 0.5;
    } else {
      d = previous;
      lambda *= 5.0;
    }
    if (std::abs(step) < 1e-4 * std::abs(d)) break;
  }
  out.inverse_distance = d;
  out.hessian = H;
  for (const Target& t : targets) {
    const TargetEvaluation e = evaluate(t, false);
    if (e.valid && e.raw_energy <= invalid_energy) ++out.num_good_residuals;
  }
  if (!(H >= opts.min_hessian))
    out.verdict = NewPointVerdict::kUnobserved;
  else if (out.num_good_residuals < opts.min_good_residuals || !(d > 0.0) || !std::isfinite(d))
    out.verdict = NewPointVerdict::kInconsistent;
  else
    out.verdict = NewPointVerdict::kAccepted;
  return out;
}

}  // namespace omnidso
