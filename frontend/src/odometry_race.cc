// The initialisation race (odometry.hpp, InitializationRaceOptions): whether it applies, each
// side's cost once its first window holds race.keyframes keyframes, and the decision.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <omnidso/frontend/frame_placement.hpp>

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

namespace {

double raceCost(const RaceSide& side, int common_start) {
  const double inf = std::numeric_limits<double>::infinity();
  if (side.start_frame > common_start) return inf;
  return side.lost && std::isnan(side.cost) ? inf : side.cost;
}

}  // namespace

RaceDecision decideRace(const RaceSide& configured, const RaceSide& rival, double switch_gain,
                        double same_start_deg) {
  RaceDecision d;
  d.common_start = std::min(configured.start_frame, rival.start_frame);
  d.configured_cost = raceCost(configured, d.common_start);
  d.rival_cost = raceCost(rival, d.common_start);
  if (configured.T_start_current && rival.T_start_current &&
      configured.start_frame == rival.start_frame) {
    const SE3d& a = *configured.T_start_current;
    const SE3d& b = *rival.T_start_current;
    constexpr double kDeg = 180.0 / M_PI;
    d.rotation_apart_deg = a.rotation().angularDistance(b.rotation()) * kDeg;
    const double na = a.translation().norm(), nb = b.translation().norm();
    if (na > 0.0 && nb > 0.0)
      d.direction_apart_deg =
          std::acos(std::clamp(a.translation().dot(b.translation()) / (na * nb), -1.0, 1.0)) * kDeg;
  }
  if (std::isnan(d.configured_cost) || std::isnan(d.rival_cost)) return d;
  d.outcome = d.rival_cost < switch_gain * d.configured_cost ? RaceOutcome::kTakeRival
                                                             : RaceOutcome::kKeepConfigured;
  // NaN angles compare false: not the same start.
  d.same_start = same_start_deg > 0.0 && d.rotation_apart_deg <= same_start_deg &&
                 d.direction_apart_deg <= same_start_deg;
  if (d.same_start) d.outcome = RaceOutcome::kKeepConfigured;
  return d;
}

void Odometry::settleRace() {
  const Impl& mine = *impl_;
  const Impl& rival = *rival_;
  // A rival that snapped on the same frame from the same first frame and adopted the same
  // start there (its initial pose the same, bit for bit) computed the same.
  const bool twins = mine.race_snap_frame >= 0 && mine.race_snap_frame == rival.race_snap_frame &&
                     mine.race_first_frame == rival.race_first_frame &&
                     mine.race_initial_pose == rival.race_initial_pose;
  auto raceSide = [](const Impl& side) {
    RaceSide s{side.race_first_frame >= 0 ? side.race_first_frame : side.first_frame_index,
               side.race_cost, side.segment > 0};
    // Both sides have just processed the same frame.
    const FrameRecord& current = side.frames.back();
    if (side.segment == 0 && side.race_first_frame >= 0 && current.tracked)
      s.T_start_current = side.keyframePose(side.race_first_frame).inverse() *
                          placeByReference(side.keyframePose(current.reference_keyframe),
                                           current.T_frame_ref);
    return s;
  };
  const RaceSide mine_side = raceSide(mine), rival_side = raceSide(rival);
  const RaceDecision decision = decideRace(mine_side, rival_side, mine.options.race.switch_gain,
                                           mine.options.race.same_start_deg);
  const bool timed_out = static_cast<int>(mine.frames.size()) >= mine.options.race.max_frames;
  if (!twins && decision.outcome == RaceOutcome::kUndecided && !timed_out) return;
  std::ostringstream m;
  m << "initialisation race: ";
  bool take_rival = false;
  if (twins) {
    m << "the rival snap (" << rival.options.initializer.snap_parallax_deg << "°) came on the same "
      << "frame; one start kept";
  } else if (decision.outcome == RaceOutcome::kUndecided) {
    m << "undecided after " << mine.frames.size() << " frames; the configured start kept";
  } else {
    take_rival = decision.outcome == RaceOutcome::kTakeRival;
    auto side = [&](const RaceSide& s, double cost, double snap_deg) {
      std::ostringstream o;
      o << cost << " (snap at " << snap_deg << "°";
      if (s.start_frame > decision.common_start)
        o << "; from frame " << s.start_frame << ", not " << decision.common_start;
      o << ")";
      return o.str();
    };
    m << "window cost RMS at " << mine.options.race.keyframes << " keyframes "
      << side(mine_side, decision.configured_cost, snapParallaxDeg(mine.options.initializer))
      << " against "
      << side(rival_side, decision.rival_cost, rival.options.initializer.snap_parallax_deg);
    if (!std::isnan(decision.rotation_apart_deg))
      m << ", the starts " << decision.rotation_apart_deg << "° apart in rotation and "
        << decision.direction_apart_deg << "° in the direction of travel at frame "
        << mine.frames.back().index;
    m << ": "
      << (take_rival              ? "the rival's start taken"
          : decision.same_start ? "the same start; the configured one kept"
                                : "the configured start kept");
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
