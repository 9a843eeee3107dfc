// A segment's start and end (odometry.hpp, step 1). Start: frames go to the Initializer
// until the baseline to the segment's first frame suffices (or, after
// initializer.max_frames, the first frame is replaced); then both become the first two
// keyframes of a new SlidingWindow with the initialiser's points, which is optimised once
// and gives the first tracking reference. End: tracking lost — the window's estimates are
// kept (keyframe poses, active points, intrinsics), the window is dropped and a new segment
// starts from the frame that was lost.
#include <algorithm>
#include <sstream>

#include "odometry_impl.hpp"

namespace omnidso {

void Odometry::Impl::initialize(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                                double exposure) {
  if (!initializer->hasFirstFrame()) {
    initializer->setFirstFrame(pyramid, exposure);
    first_frame_index = record.index;
    first_pyramid = pyramid;
    first_exposure = exposure;
    return;
  }
  const InitializationResult init = initializer->addFrame(*pyramid, exposure);
  if (!init.done) {
    if (initializer->numFramesTried() >= options.initializer.max_frames) {
      say("initialisation: no sufficient parallax after " +
          std::to_string(initializer->numFramesTried()) + " frames (" + initializer->status() +
          "); restarting from frame " + std::to_string(record.index));
      initializer->setFirstFrame(pyramid, exposure);
      first_frame_index = record.index;
      first_pyramid = pyramid;
      first_exposure = exposure;
    }
    return;
  }
  WindowOptions window_options = options.window;
  // Every window point was a candidate of one of the N_f hosts (the first keyframe's came
  // from the initialiser's num_points), however finely activation's grid packs them
  // (activation_density.hpp); one keyframe's worth more leaves room for the selector's counts,
  // which are approximate. The window holds 1.2 num_points on average (D3).
  const int per_keyframe = std::max(options.num_candidates, options.num_points);
  window_options.max_points = std::max(window_options.max_points,
                                       (window_options.max_keyframes + 1) * per_keyframe);
  window = std::make_unique<SlidingWindow>(camera.modelName(), camera.params(), window_options);
  window->setTaskPool(pool.get());
  activation_density.reset();
  FrameRecord& first = frames[first_frame_index];
  window->addKeyframe(first.index, first.timestamp, first_exposure, SE3d(),
                      Eigen::Vector2d::Zero(), first_pyramid);
  keyframes[first.index] = {first.index, first.timestamp, segment, SE3d()};
  first.tracked = true;
  first.is_keyframe = true;
  first.segment = segment;
  first.reference_keyframe = first.index;
  const SE3d T_world_frame = init.T_frame_first.inverse();
  window->addKeyframe(record.index, record.timestamp, exposure, T_world_frame,
                      init.frame_affine, pyramid);
  keyframes[record.index] = {record.index, record.timestamp, segment, T_world_frame};
  for (size_t i = 0; i < init.pixels.size(); ++i)
    window->addPoint(first.index, init.pixels[i], init.inverse_distances[i]);
  noteRaceCost(window->optimize());
  if (segment == 0) {
    race_first_frame = first.index;
    race_snap_frame = first.index + init.snapped_at;
    init.T_frame_first.toParameters(race_initial_pose.data());
  }
  window->removeOutliers();
  refreshKeyframeRecords();
  selectImmaturePoints(record.index, *pyramid);
  setTrackingReference(record.index);
  record.tracked = true;
  record.is_keyframe = true;
  record.reference_keyframe = record.index;
  last_affine = Eigen::Vector2d(window->keyframe(record.index).affine[0],
                                window->keyframe(record.index).affine[1]);
  last_exposure = exposure;
  T_world_last = window->keyframe(record.index).T_world_cam();
  // The velocity model's previous frame: one frame's motion back (InitializationResult), not
  // the first frame, which can lie tens of frames back.
  T_world_prev = T_world_last * init.T_frame_previous;
  initialized = true;
  std::ostringstream m;
  m << "segment " << segment << ": initialised at frame " << record.index << " from frame "
    << first.index << " (parallax " << init.parallax_px << " px, " << init.parallax_deg << "°, "
    << window->numPoints() << " points; snapped at frame " << first.index + init.snapped_at << ")";
  say(m.str());
}

void Odometry::Impl::loseTracking(const FrameRecord& record,
                                  std::shared_ptr<const ImagePyramid> pyramid, double exposure) {
  say("segment " + std::to_string(segment) + ": tracking lost at frame " +
      std::to_string(record.index) + "; re-initialising");
  refreshKeyframeRecords();
  visitActivePoints([this](const OdometryPoint& p) { retirePoint(p); });
  last_intrinsics = window->intrinsics();
  window.reset();
  {
    std::lock_guard<std::mutex> lock(reference_mutex);
    published = {};
  }
  reference = {};
  immature.clear();
  initialized = false;
  ++segment;
  newInitializer();
  initializer->setFirstFrame(pyramid, exposure);
  first_frame_index = record.index;
  first_pyramid = pyramid;
  first_exposure = exposure;
  last_rmse = std::numeric_limits<double>::infinity();
}

}  // namespace omnidso
