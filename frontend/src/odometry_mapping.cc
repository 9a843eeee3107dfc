// The mapping side of the odometry (odometry.hpp, steps 3 and 5): every window keyframe's
// immature points are searched along their epipolar curves in the tracked frame, its pose
// placed by its tracking reference's current estimate (frame_placement.hpp); a keyframe
// then enters the window, converged candidates are activated (odometry_activation.cc), the
// window is optimised, outliers removed, the keyframes the policy picks are marginalised
// (their candidates with them), and the new keyframe gets its own candidates and becomes
// the tracking reference. Timings of the stages go to the frame's record.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <omnidso/core/task_pool.hpp>
#include <omnidso/core/timing.hpp>

#include "odometry_impl.hpp"

namespace omnidso {
namespace {
// Immature points per task of the search: a trace takes a few microseconds, a task hand-off
// about one.
constexpr int kTraceChunk = 32;
}  // namespace

SE3d Odometry::Impl::placeInWindow(const MappingJob& job) const {
  const std::vector<int> ids = window->keyframeIds();
  if (std::find(ids.begin(), ids.end(), job.reference_id) == ids.end()) return job.T_world_frame;
  return placeByReference(window->keyframe(job.reference_id).T_world_cam(), job.T_frame_reference);
}

void Odometry::Impl::map(const MappingJob& job) {
  Stopwatch watch;
  const SE3d T_world_frame = placeInWindow(job);
  const SE3d T_frame_world = T_world_frame.inverse();
  for (auto& [host_id, list] : immature) {
    const WindowKeyframe& host = window->keyframe(host_id);
    const SE3d T_frame_host = T_frame_world * host.T_world_cam();
    AffineTransfer transfer;
    transfer.a = job.exposure * std::exp(job.affine.x()) / (host.exposure * std::exp(host.affine[0]));
    transfer.b = job.affine.y() - transfer.a * host.affine[1];
    // Each trace reads the frame and writes only its own point: the points are traced in
    // chunks on the compute threads (task_pool.hpp) and the list is compacted in order.
    std::vector<std::uint8_t> dropped(list.size(), 0);
    const int num_points = static_cast<int>(list.size());
    const int num_chunks = (num_points + kTraceChunk - 1) / kTraceChunk;
    runTasks(pool.get(), num_chunks, [&](int chunk) {
      const int end = std::min(num_points, (chunk + 1) * kTraceChunk);
      for (int i = chunk * kTraceChunk; i < end; ++i) {
        const TraceResult r =
            traceImmaturePoint(list[i], camera, T_frame_host, job.pyramid->level(0),
                               job.pyramid->gradients(0), transfer, options.epipolar,
                               job.pyramid->content(0));
        dropped[i] = r.status == TraceStatus::kOutlier || r.status == TraceStatus::kOutOfBounds;
      }
    });
    std::vector<ImmaturePoint> keep;
    keep.reserve(list.size());
    for (int i = 0; i < num_points; ++i)
      if (!dropped[i]) keep.push_back(list[i]);
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
    makeKeyframe(record, job.pyramid, job.exposure, T_world_frame, job.affine);
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
  noteRaceCost(window->optimize());
  record.timing.window_ms = stage.lapMs();
  window->removeOutliers();
  refreshKeyframeRecords();
  record.timing.outliers_ms = stage.lapMs();
  // The new keyframe's candidates depend only on its image, the mask and the seed: with
  // compute threads they are selected while the window marginalises (two tasks that share
  // nothing). Either way their time is part of marginalization_ms.
  std::vector<ImmaturePoint> candidates;
  runTasks(pool.get(), 2, [&](int task) {
    if (task == 0) {
      for (int id : leaving) window->marginalizeKeyframe(id);
    } else {
      candidates = selectCandidates(record.index, *pyramid);
    }
  });
  for (int id : leaving) immature.erase(id);
  record.timing.marginalization_ms = stage.lapMs();
  immature[record.index] = std::move(candidates);
  collectMarginalizedPoints();
  setTrackingReference(record.index);
  record.timing.selection_ms = stage.lapMs();
}

void Odometry::Impl::selectImmaturePoints(int id, const ImagePyramid& pyramid) {
  immature[id] = selectCandidates(id, pyramid);
}

std::vector<ImmaturePoint> Odometry::Impl::selectCandidates(int id,
                                                            const ImagePyramid& pyramid) const {
  PixelSelectorOptions selection = options.initializer.selection;
  selection.desired_points = options.num_candidates;
  selection.seed = options.seed + static_cast<std::uint64_t>(id);
  std::vector<ImmaturePoint> list;
  for (const SelectedPixel& p : selectPixels(pyramid, mask, selection)) {
    ImmaturePoint point;
    if (makeImmaturePoint(camera, pyramid.level(0), pyramid.gradients(0), id,
                          p.pixel.cast<double>(), &point, options.pattern_spread))
      list.push_back(point);
  }
  return list;
}

void Odometry::Impl::collectMarginalizedPoints() {
  for (const MarginalizedPoint& m : window->takeMarginalizedPoints())
    retirePoint({m.position_world.cast<float>(), m.intensity, segment});
}

}  // namespace omnidso
