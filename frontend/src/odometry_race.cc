// The initialisation race (odometry.hpp, InitializationRaceOptions): whether it applies, each
// side's cost once its first window holds race.keyframes keyframes, and the decision.
#include <cmath>
#include <limits>
#include <sstream>

#include "odometry_impl.hpp"

namespace omnidso {

bool raceApplies(const OdometryOptions& o) {
  return !o.realtime && o.race.rival_snap_parallax_deg > 0.0 &&
         o.race.rival_snap_parallax_deg < snapParallaxDeg(o.initializer);
}

OdometryOptions raceRivalOptions(const OdometryOptions& options) {
  OdometryOptions rival = options;
  rival.initializer.snap_parallax_deg = options.race.rival_snap_parallax_deg;
  rival.initializer.snap_translation_start_gain = options.race.rival_snap_translation_start_gain;
  return rival;
}

void Odometry::Impl::noteRaceCost(const WindowSolveSummary& summary) {
  if (segment != 0 || !std::isnan(race_cost) || summary.num_residuals <= 0 ||
      window->numKeyframes() < options.race.keyframes)
    return;
  race_cost = std::sqrt(2.0 * summary.final_cost / (kWindowPatternSize * summary.num_residuals));
}

void Odometry::settleRace() {
  const Impl& mine = *impl_;
  const Impl& rival = *rival_;
  // A rival that snapped on the same frame from the same first frame and adopted the same
  // start there (its initial pose the same, bit for bit) computed the same.
  const bool twins = mine.race_snap_frame >= 0 && mine.race_snap_frame == rival.race_snap_frame &&
                     mine.race_first_frame == rival.race_first_frame &&
                     mine.race_initial_pose == rival.race_initial_pose;
  // A side that lost tracking before its window held race.keyframes keyframes: infinite cost.
  const double inf = std::numeric_limits<double>::infinity();
  const double mine_cost = mine.segment > 0 && std::isnan(mine.race_cost) ? inf : mine.race_cost;
  const double rival_cost =
      rival.segment > 0 && std::isnan(rival.race_cost) ? inf : rival.race_cost;
  const bool decided = !std::isnan(mine_cost) && !std::isnan(rival_cost);
  const bool timed_out = static_cast<int>(mine.frames.size()) >= mine.options.race.max_frames;
  if (!twins && !decided && !timed_out) return;
  std::ostringstream m;
  m << "initialisation race: ";
  bool take_rival = false;
  if (twins) {
    m << "the rival snap (" << rival.options.initializer.snap_parallax_deg << "°) came on the same "
      << "frame; one start kept";
  } else if (!decided) {
    m << "undecided after " << mine.frames.size() << " frames; the configured start kept";
  } else {
    take_rival = rival_cost < mine.options.race.switch_gain * mine_cost;
    m << "window cost RMS at " << mine.options.race.keyframes << " keyframes " << mine_cost
      << " (snap at " << snapParallaxDeg(mine.options.initializer) << "°) against " << rival_cost
      << " (snap at " << rival.options.initializer.snap_parallax_deg << "°): "
      << (take_rival ? "the rival's start taken" : "the configured start kept");
  }
  if (take_rival) {
    // The rival kept its retired points (it had no sink): they go where the user asked.
    rival_->retired_point_sink = std::move(impl_->retired_point_sink);
    if (rival_->retired_point_sink) {
      for (const OdometryPoint& p : rival_->points) rival_->retired_point_sink(p);
      rival_->points.clear();
    }
    std::swap(impl_, rival_);
  }
  impl_->say(m.str());
  rival_.reset();
}

}  // namespace omnidso
