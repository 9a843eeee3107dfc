// The tracking side of the odometry (odometry.hpp, steps 2 and 4) and its hand-off to
// mapping. A frame is aligned to the newest published tracking reference (CoarseTracker with
// DSO's motion hypotheses), the keyframe decision is taken, and the frame goes to mapping as
// a MappingJob: at once in the deterministic mode, through the MappingWorker queue in the
// real-time mode, where a lagging mapper skips non-keyframes' search. Besides the frame
// records, the reference is all the two threads exchange: mapping publishes it under
// reference_mutex (setTrackingReference), tracking adopts it at its next frame
// (adoptPublishedReference).
#include <cmath>
#include <utility>
#include <omnidso/core/timing.hpp>
#include <omnidso/frontend/affine_gauge.hpp>
#include <omnidso/frontend/frame_placement.hpp>
#include <omnidso/frontend/reference_depth_consistency.hpp>

#include "odometry_impl.hpp"

namespace omnidso {

void Odometry::Impl::trackFrame(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                                double exposure) {
  Stopwatch watch;
  adoptPublishedReference();
  const TrackingReference& ref = reference;
  const SE3d T_ref_world = ref.T_world_ref.inverse();
  const SE3d T_last_ref = (T_ref_world * T_world_last).inverse();
  const SE3d velocity = T_world_last.inverse() * T_world_prev;  // T_last_prev
  const TrackingResult tracking =
      ref.tracker->track(*pyramid, exposure, ref.tracker->makeHypotheses(T_last_ref, velocity),
                         last_affine, last_rmse);
  if (!tracking.ok) {
    drainMapping();
    loseTracking(record, pyramid, exposure);
    record.timing.tracking_ms = watch.elapsedMs();
    return;
  }
  const SE3d T_world_frame = ref.T_world_ref * tracking.T_frame_ref.inverse();
  record.tracked = true;
  record.reference_keyframe = ref.id;
  record.T_frame_ref = tracking.T_frame_ref;
  last_rmse = tracking.rmse;
  if (!std::isfinite(first_rmse)) first_rmse = tracking.rmse;

  const double brightness = exposure * std::exp(tracking.affine.x()) /
                            (ref.exposure * std::exp(ref.affine.x()));
  const KeyframeDecision decision =
      decideKeyframe(tracking, brightness, first_rmse, content_extent.width,
                     content_extent.height, options.keyframe_decision);
  T_world_prev = T_world_last;
  T_world_last = T_world_frame;
  last_affine = tracking.affine;
  last_exposure = exposure;
  ++frames_since_keyframe;
  const bool forced = options.max_keyframe_interval_frames > 0 &&
                      frames_since_keyframe >= options.max_keyframe_interval_frames;
  const MappingJob job{&record,        pyramid,
                       exposure,       T_world_frame,
                       tracking.affine, decision.make_keyframe || forced,
                       ref.id,         tracking.T_frame_ref};
  if (job.make_keyframe) frames_since_keyframe = 0;
  record.timing.tracking_ms = watch.lapMs();
  if (worker) {
    if (job.make_keyframe) tracked_keyframe_affine[record.index] = tracking.affine;
    // A lagging mapper skips the search in non-keyframes (DSO does the same); keyframes
    // are always made.
    if (job.make_keyframe || worker->pending() < 2) worker->push([this, job] { map(job); });
    return;
  }
  map(job);
  if (record.is_keyframe) {  // continue from the window's estimate of the new keyframe
    const WindowKeyframe& kf = window->keyframe(record.index);
    last_affine = Eigen::Vector2d(kf.affine[0], kf.affine[1]);
    T_world_last = kf.T_world_cam();
    // The velocity's previous frame in the same estimate (frame_placement.hpp).
    const FrameRecord* previous = record.index > 0 ? &frames[record.index - 1] : nullptr;
    if (previous && previous->tracked && previous->segment == record.segment)
      T_world_prev = poseInCurrentEstimate(*previous, [this](int id) { return keyframePose(id); });
  }
}

void Odometry::Impl::setTrackingReference(int id) {
  const WindowKeyframe& kf = window->keyframe(id);
  const SE3d T_kf_world = kf.T_world_cam().inverse();
  std::vector<TrackingReferencePoint> refs;
  for (const auto& [pid, point] : window->points()) {
    if (!(point->inverse_distance > 0.0)) continue;
    const Eigen::Vector3d x = T_kf_world * window->pointInWorld(*point);
    Eigen::Vector2d u;
    if (!camera.project(x, u)) continue;
    refs.push_back({u, 1.0 / x.norm()});
  }
  refs = keepConsistentDepths(std::move(refs), options.reference_depths);
  auto tracker = std::make_shared<CoarseTracker>(camera, options.tracker);
  tracker->setReference(kf.pyramid, kf.exposure, Eigen::Vector2d(kf.affine[0], kf.affine[1]), refs);
  std::lock_guard<std::mutex> lock(reference_mutex);
  published = {std::move(tracker), id, kf.T_world_cam(), kf.exposure,
               Eigen::Vector2d(kf.affine[0], kf.affine[1])};
}

void Odometry::Impl::adoptPublishedReference() {
  std::lock_guard<std::mutex> lock(reference_mutex);
  if (published.id == reference.id && published.tracker == reference.tracker) return;
  reference = published;
  first_rmse = std::numeric_limits<double>::infinity();
  // The deterministic mode continues from the window's affine of each new keyframe (trackFrame).
  // The real-time mode's frames have moved on by then, so the last frame's affine is carried
  // into the keyframe's new gauge instead, keeping its transfer from the keyframe
  // (affine_gauge.hpp): without exposure times the window's brightness is free and drifts, and
  // a frame held (by the tracker's affine prior) to a brightness in the old gauge against a
  // reference in the new one was misaligned until keyframes came every other frame and
  // tracking was lost (docs/performance.md, "The real-time mode without exposure times").
  const auto tracked = tracked_keyframe_affine.find(reference.id);
  if (tracked != tracked_keyframe_affine.end())
    last_affine = affineInMovedKeyframeGauge(last_affine, last_exposure, tracked->second,
                                             reference.affine, reference.exposure);
  tracked_keyframe_affine.erase(tracked_keyframe_affine.begin(),
                                tracked_keyframe_affine.upper_bound(reference.id));
}

void Odometry::Impl::drainMapping() {
  if (worker) worker->drain();
}

}  // namespace omnidso
