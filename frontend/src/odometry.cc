// The Odometry facade (odometry.hpp): the options completed from the camera (pyramid depth,
// content margin, search range), the frame's way in — initialisation or tracking — and the
// read accessors, which in the real-time mode first wait for the mapping thread. The steps
// themselves are in the files odometry_impl.hpp lists.
#include <algorithm>
#include <cmath>
#include <omnidso/backend/outlier_threshold.hpp>
#include <omnidso/backend/photometric_factory.hpp>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/timing.hpp>

#include "odometry_impl.hpp"

namespace omnidso {

int defaultContentMarginPx(int pattern_spread) {
  return hostPatchReachPx<kWindowPatternSize>(pattern_spread);
}

Odometry::Impl::Impl(const Camera& c, OdometryOptions o, const Mask& image_mask)
    : camera(c),
      mask(validityMask(c)),
      options(std::move(o)),
      activation_density(options.activation_density),
      last_intrinsics(c.params()) {
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
  // The keyframe decision's image size: the content's box, the frame where it has none.
  content_extent = contentExtent(mask);
  if (content_extent.width == 0) content_extent = {camera.width(), camera.height()};
  const bool all_content = std::all_of(mask.data(), mask.data() + mask.size(),
                                       [](std::uint8_t m) { return m != 0; });
  if (options.reject_targets_outside_content && !all_content)
    content_levels = std::make_shared<const std::vector<Mask>>(
        contentPyramid(mask, options.pyramid_levels));
  options.tracker.num_levels = std::min(options.tracker.num_levels, options.pyramid_levels);
  if (options.epipolar.max_search_px <= 0)
    options.epipolar.max_search_px = 0.027 * (camera.width() + camera.height());
  // One camera encoding for residuals and selection (`selection.camera_encoding` reads it).
  options.initializer.selection.encoding = options.camera_encoding;
  // One pattern spread for every pattern user.
  if (options.pattern_spread < 1 || options.pattern_spread > 8)
    throw Error("Odometry: pattern_spread must lie in 1 … 8 (got " +
                std::to_string(options.pattern_spread) + ")");
  options.window.pattern_spread = options.pattern_spread;
  options.initializer.pattern_spread = options.pattern_spread;
  if (options.content_margin_px < 0)
    options.content_margin_px = defaultContentMarginPx(options.pattern_spread);
  mask = erodeContent(mask, options.content_margin_px);
  content_area = static_cast<double>(std::count_if(
      mask.data(), mask.data() + mask.size(), [](std::uint8_t m) { return m != 0; }));
  // The search's interval half-width σ + e |c| / a (epipolar_search.hpp) must be positive.
  if (!(options.epipolar.match_sigma_px > 0.0) || !(options.epipolar.curve_offset_px >= 0.0))
    throw Error("Odometry: epipolar.match_sigma_px must be > 0 and epipolar.curve_offset_px >= 0 "
                "(got " + std::to_string(options.epipolar.match_sigma_px) + " and " +
                std::to_string(options.epipolar.curve_offset_px) + ")");
  // The window is made at initialisation: its settings are checked here, before any frame.
  checkOutlierThresholdOptions(options.window.outlier_threshold);
  validate(options.reference_depths);
  options.window.num_threads = std::max(1, options.window.num_threads);
  if (options.compute_threads < 0)
    throw Error("Odometry: compute_threads is " + std::to_string(options.compute_threads) +
                " (0: the hardware threads, up to 8; 1: none besides the caller)");
  const int compute_threads =
      options.compute_threads == 0 ? defaultComputeThreads() : options.compute_threads;
  if (compute_threads > 1) pool = std::make_unique<TaskPool>(compute_threads);
  newInitializer();
  if (options.realtime) worker = std::make_unique<MappingWorker>();
}

void Odometry::Impl::newInitializer() {
  InitializerOptions init = options.initializer;
  init.num_levels = options.pyramid_levels;
  init.selection.desired_points = options.num_points;
  init.selection.seed = options.seed;
  initializer = std::make_unique<Initializer>(camera, mask, init);
  initializer->setTaskPool(pool.get());
}

SE3d Odometry::Impl::keyframePose(int id) const {
  if (window) {
    for (int wid : window->keyframeIds())
      if (wid == id) return window->keyframe(id).T_world_cam();
  }
  return keyframes.at(id).T_world_cam;
}

void Odometry::Impl::refreshKeyframeRecords() {
  for (int id : window->keyframeIds())
    keyframes[id].T_world_cam = window->keyframe(id).T_world_cam();
}

void Odometry::Impl::visitActivePoints(
    const std::function<void(const OdometryPoint&)>& visit) const {
  for (const auto& [pid, point] : window->points())
    if (point->inverse_distance > 0.0)
      visit({window->pointInWorld(*point).cast<float>(), point->hostIntensity(), segment});
}

void Odometry::Impl::retirePoint(const OdometryPoint& point) {
  if (retired_point_sink)
    retired_point_sink(point);
  else
    points.push_back(point);
}

Odometry::Odometry(const Camera& camera, OdometryOptions options, const Mask& image_mask) {
  if (camera.hasDistortion())
    throw Error("Odometry: camera model '" + camera.modelName() +
                "' has distortion; rectify the images to '" +
                camera.undistortedModel().modelName() + "' first");
  if (options.race.keyframes < 2 || options.race.keyframes > options.window.max_keyframes ||
      !(options.race.switch_gain > 0.0) || options.race.max_frames < 1 ||
      !(options.race.rival_snap_translation_start_gain > 0.0) ||
      std::isnan(options.race.same_start_deg))
    throw Error("Odometry: race.keyframes must lie in 2 … window.max_keyframes, "
                "race.switch_gain and race.rival_snap_translation_start_gain be > 0, "
                "race.same_start_deg a number and race.max_frames ≥ 1 (got " +
                std::to_string(options.race.keyframes) + ", " +
                std::to_string(options.race.switch_gain) + ", " +
                std::to_string(options.race.same_start_deg) + ", " +
                std::to_string(options.race.rival_snap_translation_start_gain) + ", " +
                std::to_string(options.race.max_frames) + ")");
  if (raceApplies(options))
    rival_ = std::make_unique<Impl>(camera, raceRivalOptions(options), image_mask);
  impl_ = std::make_unique<Impl>(camera, std::move(options), image_mask);
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
  auto pyramid =
      std::make_shared<const ImagePyramid>(image, s.options.pyramid_levels, s.content_levels,
                                           s.options.noise_in_encoding
                                               ? s.options.camera_encoding
                                               : nullptr);
  impl_->addFrame(pyramid, timestamp, exposure);
  if (rival_) {
    rival_->addFrame(pyramid, timestamp, exposure);
    settleRace();
  }
  return impl_->frames.back();
}

FrameRecord& Odometry::Impl::addFrame(std::shared_ptr<const ImagePyramid> pyramid,
                                      double timestamp, double exposure) {
  FrameRecord record;
  record.index = static_cast<int>(frames.size());
  record.timestamp = timestamp;
  record.segment = segment;
  frames.push_back(record);
  FrameRecord& current = frames.back();
  Stopwatch watch;
  if (!initialized) {
    initialize(current, pyramid, exposure);
    current.timing.mapping_ms = watch.elapsedMs();
  } else {
    trackFrame(current, pyramid, exposure);
  }
  current.segment = current.tracked ? current.segment : segment;
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
  // Every frame, keyframes too, through its tracked pose (frames.txt).
  return placeByReference(impl_->keyframePose(frame.reference_keyframe), frame.T_frame_ref);
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

void Odometry::setRetiredPointSink(std::function<void(const OdometryPoint&)> sink) {
  impl_->retired_point_sink = std::move(sink);
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
