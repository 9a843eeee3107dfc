#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <omnidso/frontend/mapping_worker.hpp>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <sstream>

namespace omnidso {

struct Odometry::Impl {
  Camera camera;
  Mask mask;
  OdometryOptions options;

  std::unique_ptr<SlidingWindow> window;
  // What tracking aligns to: set by the mapping side (setTrackingReference), picked up by
  // the tracking side at its next frame (adoptPublishedReference). In the real-time mode the
  // two sides are two threads, hence the mutex.
  struct TrackingReference {
    std::shared_ptr<const CoarseTracker> tracker;
    int id = -1;
    SE3d T_world_ref;
    double exposure = 1.0;
    Eigen::Vector2d affine = Eigen::Vector2d::Zero();
  };
  std::mutex reference_mutex;
  TrackingReference published;  // guarded by reference_mutex
  TrackingReference reference;  // the tracking side's copy
  std::unique_ptr<Initializer> initializer;
  std::map<int, std::vector<ImmaturePoint>> immature;  // by host keyframe

  std::deque<FrameRecord> frames;  // a deque: records stay put while the mapper writes timings
  std::map<int, KeyframeRecord> keyframes;  // every keyframe ever; poses kept current
  std::deque<OdometryPoint> points;         // marginalised points (a deque: no 2× regrowth)
  std::vector<std::string> log;

  bool initialized = false;
  int segment = 0;
  int first_frame_index = -1;
  std::shared_ptr<const ImagePyramid> first_pyramid;
  double first_exposure = 1.0;
  double last_rmse = std::numeric_limits<double>::infinity();
  double first_rmse = std::numeric_limits<double>::infinity();  // since the newest keyframe
  SE3d T_world_last, T_world_prev;
  int frames_tracked = 0;
  Eigen::Vector2d last_affine = Eigen::Vector2d::Zero();
  int frames_since_keyframe = 0;
  Eigen::VectorXd last_intrinsics;  // of the last finished segment

  Impl(const Camera& c, OdometryOptions o, const Mask& image_mask)
      : camera(c), mask(validityMask(c)), options(std::move(o)), last_intrinsics(c.params()) {
    if (!image_mask.empty()) {
      if (image_mask.width() != c.width() || image_mask.height() != c.height())
        throw Error("Odometry: the image mask is " + std::to_string(image_mask.width()) + "x" +
                    std::to_string(image_mask.height()) + ", the camera " +
                    std::to_string(c.width()) + "x" + std::to_string(c.height()));
      for (size_t i = 0; i < mask.size(); ++i)
        if (!image_mask.data()[i]) mask.data()[i] = 0;
    }
    if (options.pyramid_levels <= 0)
      options.pyramid_levels = pyramidLevelsForImage(camera.width(), camera.height());
    options.tracker.num_levels = std::min(options.tracker.num_levels, options.pyramid_levels);
    // Keep every pyramid level clear of the content's edge (content_mask.hpp): a level-L
    // sample and its central differences reach 2^L pixels of level 0, the pattern 2 more.
    if (options.content_margin_px < 0)
      options.content_margin_px = (1 << options.pyramid_levels) + 3;
    mask = erodeContent(mask, options.content_margin_px);
    if (options.epipolar.max_search_px <= 0)
      options.epipolar.max_search_px = 0.027 * (camera.width() + camera.height());
    options.window.num_threads = std::max(1, options.window.num_threads);
    newInitializer();
    if (options.realtime) worker = std::make_unique<MappingWorker>();
  }

  void newInitializer() {
    InitializerOptions init = options.initializer;
    init.num_levels = options.pyramid_levels;
    init.selection.desired_points = options.num_points;
    init.selection.seed = options.seed;
    initializer = std::make_unique<Initializer>(camera, mask, init);
  }

  SE3d keyframePose(int id) const {
    if (window) {
      for (int wid : window->keyframeIds())
        if (wid == id) return window->keyframe(id).T_world_cam();
    }
    return keyframes.at(id).T_world_cam;
  }

  void say(const std::string& message) { log.push_back(message); }

  // ---- keyframes -------------------------------------------------------------------
  void selectImmaturePoints(int id, const ImagePyramid& pyramid) {
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

  void refreshKeyframeRecords() {
    for (int id : window->keyframeIds()) keyframes[id].T_world_cam = window->keyframe(id).T_world_cam();
  }

  // The window's active points (those not at infinity), in the world.
  void visitActivePoints(const std::function<void(const OdometryPoint&)>& visit) const {
    for (const auto& [pid, point] : window->points())
      if (point->inverse_distance > 0.0)
        visit({window->pointInWorld(*point).cast<float>(), point->hostIntensity(), segment});
  }
  void appendActivePoints(std::deque<OdometryPoint>& out) const {
    visitActivePoints([&](const OdometryPoint& p) { out.push_back(p); });
  }

  void collectMarginalizedPoints() {
    for (const MarginalizedPoint& m : window->takeMarginalizedPoints())
      points.push_back({m.position_world.cast<float>(), m.intensity, segment});
  }

  void setTrackingReference(int id) {
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
    auto tracker = std::make_shared<CoarseTracker>(camera, options.tracker);
    tracker->setReference(kf.pyramid, kf.exposure, Eigen::Vector2d(kf.affine[0], kf.affine[1]), refs);
    std::lock_guard<std::mutex> lock(reference_mutex);
    published = {std::move(tracker), id, kf.T_world_cam(), kf.exposure,
                 Eigen::Vector2d(kf.affine[0], kf.affine[1])};
  }

  // Tracking side: a newer reference from the mapping side replaces the current one.
  void adoptPublishedReference() {
    std::lock_guard<std::mutex> lock(reference_mutex);
    if (published.id == reference.id && published.tracker == reference.tracker) return;
    reference = published;
    first_rmse = std::numeric_limits<double>::infinity();
  }

  // leaving: the keyframes this keyframe step will marginalise. Their points neither count
  // against num_points nor occupy a cell, and their candidates are not activated: activation
  // refills the window that remains. (With N_f = 3 the initial keyframe holds every point
  // when it leaves; counting its points left the window empty and tracking lost.)
  void activatePoints(int newest_id, const std::vector<int>& leaving) {
    const auto is_leaving = [&leaving](int id) {
      return std::find(leaving.begin(), leaving.end(), id) != leaving.end();
    };
    const WindowKeyframe& newest = window->keyframe(newest_id);
    const SE3d T_newest_world = newest.T_world_cam().inverse();
    // Occupancy grid in the newest keyframe: one point per cell keeps the map spread out.
    const double valid_area = std::max(1.0, static_cast<double>(std::count_if(
        mask.data(), mask.data() + mask.size(), [](std::uint8_t m) { return m != 0; })));
    const double cell = std::max(2.0, std::sqrt(valid_area / std::max(1, options.num_points)));
    const int gw = static_cast<int>(camera.width() / cell) + 1;
    const int gh = static_cast<int>(camera.height() / cell) + 1;
    std::vector<char> occupied(static_cast<size_t>(gw) * gh, 0);
    auto cellOf = [&](const Eigen::Vector2d& u) {
      return static_cast<size_t>(static_cast<int>(u.y() / cell)) * gw +
             static_cast<size_t>(static_cast<int>(u.x() / cell));
    };
    int num_staying = 0;
    for (const auto& [pid, point] : window->points()) {
      if (is_leaving(point->host_id)) continue;
      ++num_staying;
      if (!(point->inverse_distance > 0.0)) continue;
      Eigen::Vector2d u;
      if (camera.project(T_newest_world * window->pointInWorld(*point), u)) occupied[cellOf(u)] = 1;
    }
    for (auto& [host_id, list] : immature) {
      if (is_leaving(host_id)) continue;
      const SE3d T_world_host = window->keyframe(host_id).T_world_cam();
      std::vector<ImmaturePoint> keep;
      for (ImmaturePoint& p : list) {
        const bool converged = p.num_good_traces > 0 &&
                               (p.last_status == TraceStatus::kGood ||
                                p.last_status == TraceStatus::kSkipped) &&
                               p.last_interval_px <= options.max_activation_interval_px &&
                               p.quality >= options.min_activation_quality;
        const double d = p.inverseDistanceEstimate();
        if (!converged || num_staying >= options.num_points || !(d > 0.0)) {
          keep.push_back(p);
          continue;
        }
        Eigen::Vector2d u;
        const Eigen::Vector3d x = T_newest_world * (T_world_host * (p.bearing / d));
        const bool in_newest = camera.project(x, u);
        if (in_newest && occupied[cellOf(u)]) {
          keep.push_back(p);
          continue;
        }
        double activation_d = d;
        if (options.activation.enabled) {
          const NewPointRefinement r =
              window->refineNewPoint(host_id, p.pixel, d, options.activation);
          if (r.verdict == NewPointVerdict::kUnobserved) {
            keep.push_back(p);
            continue;
          }
          if (r.verdict == NewPointVerdict::kInconsistent) continue;  // a wrong match: drop
          activation_d = r.inverse_distance;
        }
        if (in_newest) occupied[cellOf(u)] = 1;
        if (window->addPoint(host_id, p.pixel, activation_d) < 0) continue;  // no valid residual
        ++num_staying;
      }
      list.swap(keep);
    }
  }

  void makeKeyframe(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                    double exposure, const SE3d& T_world_frame, const Eigen::Vector2d& affine) {
    window->addKeyframe(record.index, record.timestamp, exposure, T_world_frame, affine, pyramid);
    keyframes[record.index] = {record.index, record.timestamp, segment, T_world_frame};
    // DSO's order: the keyframes to marginalise are chosen once the new keyframe observes
    // the window's points, before activation, and marginalised after the optimisation.
    const std::vector<int> leaving = window->keyframesToMarginalize(options.marginalization);
    activatePoints(record.index, leaving);
    Stopwatch stage;
    window->optimize();
    record.timing.window_ms = stage.lapMs();
    window->removeOutliers();
    refreshKeyframeRecords();
    stage.restart();
    for (int id : leaving) {
      window->marginalizeKeyframe(id);
      immature.erase(id);
    }
    record.timing.marginalization_ms = stage.lapMs();
    collectMarginalizedPoints();
    selectImmaturePoints(record.index, *pyramid);
    setTrackingReference(record.index);
  }

  // ---- initialisation --------------------------------------------------------------
  void initialize(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
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
    // Activation stops at num_points active points; the initialisation's may exceed it a
    // little: room to spare, so that the slots never run out.
    window_options.max_points = std::max(window_options.max_points, 4 * options.num_points);
    window = std::make_unique<SlidingWindow>(camera.modelName(), camera.params(), window_options);
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
    window->optimize();
    window->removeOutliers();
    refreshKeyframeRecords();
    selectImmaturePoints(record.index, *pyramid);
    setTrackingReference(record.index);
    record.tracked = true;
    record.is_keyframe = true;
    record.reference_keyframe = record.index;
    last_affine = Eigen::Vector2d(window->keyframe(record.index).affine[0],
                                  window->keyframe(record.index).affine[1]);
    T_world_prev = window->keyframe(first.index).T_world_cam();
    T_world_last = window->keyframe(record.index).T_world_cam();
    initialized = true;
    std::ostringstream m;
    m << "segment " << segment << ": initialised at frame " << record.index << " from frame "
      << first.index << " (parallax " << init.parallax_px << " px, " << window->numPoints()
      << " points)";
    say(m.str());
  }

  void loseTracking(const FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
                    double exposure) {
    say("segment " + std::to_string(segment) + ": tracking lost at frame " +
        std::to_string(record.index) + "; re-initialising");
    refreshKeyframeRecords();
    appendActivePoints(points);
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

  // ---- mapping side ----------------------------------------------------------------
  // What a tracked frame hands to mapping. `record` stays valid: frames is a deque.
  struct MappingJob {
    FrameRecord* record = nullptr;
    std::shared_ptr<const ImagePyramid> pyramid;
    double exposure = 1.0;
    SE3d T_world_frame;
    Eigen::Vector2d affine = Eigen::Vector2d::Zero();
    bool make_keyframe = false;
    int reference_id = -1;  // the keyframe tracking aligned the frame to
  };

  // Epipolar-curve search of every window keyframe's immature points in the frame (step 3),
  // then, for a keyframe, the window (step 5).
  void map(const MappingJob& job) {
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
        const TraceResult r = traceImmaturePoint(p, camera, T_frame_host, job.pyramid->level(0),
                                                 job.pyramid->gradients(0), transfer, options.epipolar);
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

  // In the real-time mode: waits for the mapping thread (before re-initialising, and before
  // results are read).
  void drainMapping() {
    if (worker) worker->drain();
  }

  // ---- tracking side ---------------------------------------------------------------
  void trackFrame(FrameRecord& record, std::shared_ptr<const ImagePyramid> pyramid,
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
        decideKeyframe(tracking, brightness, first_rmse, camera.width(), camera.height(),
                       options.keyframe_decision);
    T_world_prev = T_world_last;
    T_world_last = T_world_frame;
    last_affine = tracking.affine;
    ++frames_since_keyframe;
    const bool forced = options.max_keyframe_interval_frames > 0 &&
                        frames_since_keyframe >= options.max_keyframe_interval_frames;
    const MappingJob job{&record, pyramid,         exposure, T_world_frame,
                         tracking.affine, decision.make_keyframe || forced, ref.id};
    if (job.make_keyframe) frames_since_keyframe = 0;
    record.timing.tracking_ms = watch.lapMs();
    if (worker) {
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
    }
  }

  // Declared last: destroyed first, so queued jobs finish while everything they use exists.
  std::unique_ptr<MappingWorker> worker;
};

Odometry::Odometry(const Camera& camera, OdometryOptions options, const Mask& image_mask)
    : impl_(std::make_unique<Impl>(camera, std::move(options), image_mask)) {
  if (camera.hasDistortion())
    throw Error("Odometry: camera model '" + camera.modelName() +
                "' has distortion; rectify the images to '" +
                camera.undistortedModel().modelName() + "' first");
}

Odometry::~Odometry() = default;

const FrameRecord& Odometry::addFrame(const ImageF& image, double timestamp, double exposure) {
  Impl& s = *impl_;
  if (image.width() != s.camera.width() || image.height() != s.camera.height())
    throw Error("Odometry::addFrame: image is " + std::to_string(image.width()) + "x" +
                std::to_string(image.height()) + ", the camera " +
                std::to_string(s.camera.width()) + "x" + std::to_string(s.camera.height()));
  if (!(exposure > 0.0) || !std::isfinite(exposure))
    throw Error("Odometry::addFrame: exposure must be positive (got " + std::to_string(exposure) + ")");
  FrameRecord record;
  record.index = static_cast<int>(s.frames.size());
  record.timestamp = timestamp;
  record.segment = s.segment;
  s.frames.push_back(record);
  FrameRecord& current = s.frames.back();
  auto pyramid = std::make_shared<const ImagePyramid>(image, s.options.pyramid_levels);
  Stopwatch watch;
  if (!s.initialized) {
    s.initialize(current, pyramid, exposure);
    current.timing.mapping_ms = watch.elapsedMs();
  } else {
    s.trackFrame(current, pyramid, exposure);
  }
  current.segment = current.tracked ? current.segment : s.segment;
  return current;
}

void Odometry::finish() { impl_->drainMapping(); }

const std::deque<FrameRecord>& Odometry::frames() const {
  impl_->drainMapping();
  return impl_->frames;
}

SE3d Odometry::framePose(const FrameRecord& frame) const {
  impl_->drainMapping();
  if (!frame.tracked) throw Error("Odometry::framePose: frame " + std::to_string(frame.index) + " has no pose");
  return impl_->keyframePose(frame.reference_keyframe) * frame.T_frame_ref.inverse();
}

std::vector<KeyframeRecord> Odometry::keyframes() const {
  impl_->drainMapping();
  std::vector<KeyframeRecord> out;
  for (const auto& [id, kf] : impl_->keyframes) {
    KeyframeRecord r = kf;
    r.T_world_cam = impl_->keyframePose(id);
    out.push_back(r);
  }
  return out;
}

std::vector<OdometryPoint> Odometry::points() const {
  std::vector<OdometryPoint> out;
  out.reserve(numPoints());
  forEachPoint([&](const OdometryPoint& p) { out.push_back(p); });
  return out;
}

void Odometry::forEachPoint(const std::function<void(const OdometryPoint&)>& visit) const {
  impl_->drainMapping();
  for (const OdometryPoint& p : impl_->points) visit(p);
  if (impl_->window) impl_->visitActivePoints(visit);
}

size_t Odometry::numPoints() const {
  impl_->drainMapping();
  size_t n = impl_->points.size();
  if (impl_->window)
    for (const auto& [pid, point] : impl_->window->points()) n += point->inverse_distance > 0.0;
  return n;
}

bool Odometry::initialized() const { return impl_->initialized; }

Eigen::VectorXd Odometry::intrinsics() const {
  impl_->drainMapping();
  return impl_->window ? impl_->window->intrinsics() : impl_->last_intrinsics;
}
int Odometry::numSegments() const { return impl_->segment + 1; }
const std::vector<std::string>& Odometry::log() const {
  impl_->drainMapping();
  return impl_->log;
}

std::string Odometry::initializationStatus() const {
  return impl_->initialized ? std::string() : impl_->initializer->status();
}

}  // namespace omnidso
