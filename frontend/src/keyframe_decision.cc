#include <cmath>
#include <omnidso/frontend/keyframe_decision.hpp>

namespace omnidso {

KeyframeDecision decideKeyframe(const TrackingResult& tracking, double brightness_ratio,
                                double first_rmse, int width, int height,
                                const KeyframeDecisionOptions& options) {
  KeyframeDecision decision;
  const double size = static_cast<double>(width + height);
  decision.score = options.global_weight *
                   (options.weight_flow_t * tracking.flow_t / size +
                    options.weight_flow_rt * tracking.flow_rt / size +
                    options.weight_affine * std::abs(std::log(brightness_ratio)));
  decision.rmse_grew = std::isfinite(first_rmse) && first_rmse > 0.0 &&
                       tracking.rmse > options.rmse_growth_factor * first_rmse;
  decision.make_keyframe = decision.score > 1.0 || decision.rmse_grew;
  return decision;
}

}  // namespace omnidso
