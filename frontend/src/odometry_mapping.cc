// The mapping side of the odometry (odometry.hpp, steps 3 and 5): every window keyframe's
// immature points are searched along their epipolar curves in the tracked frame; a keyframe
// then enters the window, converged candidates are activated (odometry_activation.cc), the
// window is optimised, outliers removed, the keyframes the policy picks are marginalised
// (their candidates with them), and the new keyframe gets its own candidates and becomes
// the tracking reference. Timings of the stages go to the frame's record.
#include <cmath>
#include <omnidso/core/timing.hpp>

#include "odometry_impl.hpp"

namespace omnidso {

void Odometry::Impl::map(const MappingJob& job) {
  Stopwatch watch;
  const SE3d T_frame_world = job.T_world_frame.inverse();
  for (auto& [host_id, list] : immature) {
    const WindowKeyframe& host = window->keyframe(host_id);
    const SE3d T_frame_host = T_frame_world * host.T_world_cam();
    AffineTransfer transfer;
    transfer.a = job.exposure * std::exp(job.affine.x()) / (host.exposure * std::exp(host.affine[0]));
    transfer.b = job.affine.y() - transfer.a * host.affine[1];
    std::vector<ImmaturePoint> keep;
    keep.reserve(list.size());
    for (ImmaturePoint& p : list) {
      const TraceResult r =
          traceImmaturePoint(p, camera, T_frame_host, job.pyramid->level(0),
                             job.pyramid->gradients(0), transfer, options.epipolar,
                             job.pyramid->content(0));
      if (r.status == TraceStatus::kOutlier || r.status == TraceStatus::kOutOfBounds) continue;
      keep.push_back(p);
    }
    list.swap(keep);
  }
  job.record->timing.search_ms = watch.lapMs();
  // A request made against a keyframe that is no longer the newest is stale: a keyframe
  // has been made since (the real-time mode, while tracking waited for its reference);
  // DSO likewise maps such frames as ordinary ones.
  const bool stale = job.reference_id != window->keyframeIds().back();
  if (job.make_keyframe && !stale) {
    FrameRecord& record = *job.record;
    record.is_keyframe = true;  // its own reference from now on; its pose is the window's
    record.reference_keyframe = record.index;
    record.T_frame_ref = SE3d();
    makeKeyframe(record, job.pyramid, job.exposure, job.T_world_frame, job.affine);
    record.timing.mapping_ms = watch.lapMs();
  }
}

void Odometry::Impl::makeKeyframe(FrameRecord& record,
                                  std::shared_ptr<const ImagePyramid> pyramid, double exposure,
                                  const SE3d& T_world_frame, const Eigen::Vector2d& affine) {
  Stopwatch stage;
  window->addKeyframe(record.index, record.timestamp, exposure, T_world_frame, affine, pyramid);
  keyframes[record.index] = {record.index, record.timestamp, segment, T_world_frame};
  // DSO's order: the keyframes to marginalise are chosen once the new keyframe observes the
  // window's points, before activation, and marginalised after the optimisation.
  const std::vector<int> leaving = window->keyframesToMarginalize(options.marginalization);
  activatePoints(record.index, leaving);
  record.timing.activation_ms = stage.lapMs();
  window->optimize();
  record.timing.window_ms = stage.lapMs();
  window->removeOutliers();
  refreshKeyframeRecords();
  record.timing.outliers_ms = stage.lapMs();
  for (int id : leaving) {
    window->marginalizeKeyframe(id);
    immature.erase(id);
  }
  record.timing.marginalization_ms = stage.lapMs();
  collectMarginalizedPoints();
  selectImmaturePoints(record.index, *pyramid);
  setTrackingReference(record.index);
  record.timing.selection_ms = stage.lapMs();
}

void Odometry::Impl::selectImmaturePoints(int id, const ImagePyramid& pyramid) {
  PixelSelectorOptions selection = options.initializer.selection;
  selection.desired_points = options.num_candidates;
  selection.seed = options.seed + static_cast<std::uint64_t>(id);
  std::vector<ImmaturePoint>& list = immature[id];
  for (const SelectedPixel& p : selectPixels(pyramid, mask, selection)) {
    ImmaturePoint point;
    if (makeImmaturePoint(camera, pyramid.level(0), id, p.pixel.cast<double>(), &point))
      list.push_back(point);
  }
}

void Odometry::Impl::collectMarginalizedPoints() {
  for (const MarginalizedPoint& m : window->takeMarginalizedPoints())
    retirePoint({m.position_world.cast<float>(), m.intensity, segment});
}

}  // namespace omnidso
