#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <iomanip>
#include <omnidso/cameras/rectification.hpp>
#include <sstream>
#include <thread>
#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/cli/dataset_vignette.hpp>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>
#include <omnidso/core/number_text.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/pyramid.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/synth/dataset_loading.hpp>

namespace omnidso::cli {

std::optional<double> parseNativeFov(const std::string& text) {
  const std::string prefix = "native-fov:";
  if (text.rfind(prefix, 0) != 0) return std::nullopt;
  if (const std::optional<double> fov = parseWholeNumber(text.substr(prefix.size()));
      fov && *fov > 1.0 && *fov <= 360.0)
    return *fov;
  throw Error("--camera-model: expected 'native-fov:FOV_DEG' with 1 < FOV <= 360, got '" + text + "'");
}

Mask viewAngleMask(const Camera& camera, double fov_deg) {
  Mask mask(camera.width(), camera.height());
  const double max_angle = 0.5 * fov_deg * M_PI / 180.0;
  for (int v = 0; v < camera.height(); ++v)
    for (int u = 0; u < camera.width(); ++u) {
      Eigen::Vector3d bearing;
      mask(u, v) = camera.unproject(Eigen::Vector2d(u, v), bearing) &&
                   std::acos(std::clamp(bearing.z(), -1.0, 1.0)) <= max_angle;
    }
  return mask;
}

namespace {

// The black surround of a fisheye's image circle (content_mask.hpp), on the source's grid,
// from the brightest value of each pixel over the first frames; empty when there are none.
Mask detectSourceContent(const DatasetIndex& index, const Camera& source) {
  std::vector<RawImage> first;
  for (size_t i = 0; i < std::min<size_t>(5, index.frames.size()); ++i)
    first.push_back(readRawImage(index.frames[i].image_path));
  std::vector<const ImageU16*> pixels;
  for (const RawImage& r : first)
    if (r.pixels.width() == source.width() && r.pixels.height() == source.height())
      pixels.push_back(&r.pixels);
  if (pixels.empty()) return Mask();
  const int full_scale = (1 << first.front().bit_depth) - 1;
  return detectContentMask(pixels, static_cast<int>(0.02 * full_scale));
}

// Twice the largest angle from the optical axis over the camera's valid pixels in `within`
// (every pixel when it is empty).
double maximumViewAngleDeg(const Camera& camera, const Mask& within) {
  double widest = 0.0;
  for (int v = 0; v < camera.height(); ++v)
    for (int u = 0; u < camera.width(); ++u) {
      Eigen::Vector3d bearing;
      if ((within.empty() || within(u, v)) && camera.unproject(Eigen::Vector2d(u, v), bearing))
        widest = std::max(widest, std::acos(std::clamp(bearing.normalized().z(), -1.0, 1.0)));
    }
  return 2.0 * widest * 180.0 / M_PI;
}

}  // namespace

std::optional<double> parsePinholeCrop(const std::string& text) {
  if (text == "native" || parseNativeFov(text)) return std::nullopt;
  const std::string prefix = "pinhole-crop:";
  if (text.rfind(prefix, 0) == 0) {
    if (const std::optional<double> fov = parseWholeNumber(text.substr(prefix.size()));
        fov && *fov > 1.0 && *fov < 179.0)
      return *fov;
  }
  throw Error("--camera-model: expected 'native', 'native-fov:FOV_DEG' or 'pinhole-crop:FOV_DEG' "
              "with 1 < FOV < 179, got '" +
              text + "'");
}

bool exposureTimesKnown(const DatasetIndex& index) {
  return !index.frames.empty() &&
         std::all_of(index.frames.begin(), index.frames.end(),
                     [](const DatasetFrame& f) { return f.exposure_ms > 0; });
}

std::string applyPhotometricMode(const DatasetIndex& index, OdometryOptions* options) {
  if (exposureTimesKnown(index)) return "";
  options->window.affine_prior_weight_a = 0.0;
  options->tracker.affine_prior_weight_a = 0.0;
  options->tracker.affine_in_reference_gauge = true;
  return "no exposure times: each frame's gain is left free and its offset tied to 0, in the "
         "window and in the tracker (--set window.affine_prior_weight_a=1e8 --set "
         "tracker.affine_prior_weight_a=1e8 --set tracker.affine_in_reference_gauge=false ties "
         "the gain as with exposure times)";
}

std::string applyCropPatternSpread(const DatasetIndex& index, const DatasetRunOptions& run,
                                   OdometryOptions* options) {
  const std::optional<double> crop_fov = parsePinholeCrop(run.camera_model);
  if (!crop_fov) return "";
  const Camera source = synth::datasetCamera(index, run.calib);
  const Camera crop = pinholeForFov(*crop_fov, source.width(), source.height());
  const double magnification = magnificationAtPrincipalPoint(source.undistortedModel(), crop);
  options->pattern_spread = std::clamp(static_cast<int>(std::lround(magnification)), 1, 8);
  std::ostringstream note;
  note << "the pinhole crop magnifies the source " << std::setprecision(3) << magnification
       << "x at its centre: the residual pattern is laid on steps of " << options->pattern_spread
       << " pixels (--set pattern_spread=1 for DSO's pattern)";
  return note.str();
}

DatasetRun runOdometryOnDataset(const DatasetIndex& index, const DatasetRunOptions& options) {
  const Camera source = synth::datasetCamera(index, options.calib);
  const std::optional<double> crop_fov = parsePinholeCrop(options.camera_model);
  // The odometry's camera, and the map from the raw images to it when they differ.
  Camera camera = source.undistortedModel();
  if (crop_fov) camera = pinholeForFov(*crop_fov, source.width(), source.height());
  std::optional<RectificationMap> rectification;
  Mask image_mask;
  Mask source_content;  // the content on the source's grid (empty: all of it)
  if (crop_fov || source.distortsImages()) {
    rectification = makeRectificationMap(source, camera);
    image_mask = validMask(*rectification);
  }
  if (options.detect_content) source_content = detectSourceContent(index, source);
  if (!source_content.empty()) {
    Mask content = source_content;
    if (rectification) content = remap(content, *rectification);  // 0 where any source pixel is 0 nearby
    if (image_mask.empty()) {
      image_mask = std::move(content);
    } else {
      for (size_t i = 0; i < image_mask.size(); ++i) image_mask.data()[i] &= content.data()[i];
    }
  }
  if (const std::optional<double> fov = parseNativeFov(options.camera_model)) {
    Mask within = viewAngleMask(camera, *fov);
    if (!image_mask.empty())
      for (size_t i = 0; i < within.size(); ++i) within.data()[i] &= image_mask.data()[i];
    image_mask = std::move(within);
  }
  PhotometricCalibration photometric = PhotometricCalibration::fromFiles(
      index.pcalib_path.value_or(""), index.vignette_path.value_or(""));
  if (photometric.hasVignette()) photometric.checkImageSize(source.width(), source.height());
  const size_t total = options.max_frames > 0 ? std::min(index.frames.size(), options.max_frames)
                                              : index.frames.size();
  std::optional<VignetteEstimate> vignette_estimate;
  if (!index.vignette_path && options.estimate_vignette) {
    vignette_estimate = estimateDatasetVignette(index, total, source, source_content, photometric);
    if (vignette_estimate->valid)
      photometric = PhotometricCalibration(photometric.inverseResponseTable(),
                                           vignette_estimate->map(source.width(), source.height()),
                                           "the estimated vignette");
  }

  // The camera's encoding (camera_encoding.hpp) on the odometry's image grid: the residuals'
  // weights (`noise_in_encoding`) and, with `selection.camera_encoding`, pixel selection.
  OdometryOptions odometry_options = options.odometry;
  if (odometry_options.noise_in_encoding || odometry_options.initializer.selection.camera_encoding) {
    const std::array<float, kResponseSize> table = photometric.responseSlopeTable();
    std::vector<float> slope;
    if (std::any_of(table.begin(), table.end(), [](float s) { return s != 1.f; }))
      slope.assign(table.begin(), table.end());
    ImageF vignette;
    if (photometric.hasVignette())
      vignette = rectification ? remap(photometric.vignette(), *rectification) : photometric.vignette();
    if (!slope.empty() || !vignette.empty())
      odometry_options.camera_encoding =
          std::make_shared<const CameraEncoding>(std::move(slope), vignette);
  }
  DatasetRun run{source, camera, std::make_unique<Odometry>(camera, odometry_options, image_mask),
                 std::move(vignette_estimate)};
  if (options.retired_point_sink) run.odometry->setRetiredPointSink(options.retired_point_sink);
  Stopwatch wall;
  const bool paced = options.odometry.realtime && options.playback_speed > 0.0 && total > 0;
  // Frame i as the odometry takes it (reads only what is const during the loop).
  auto load = [&](size_t i) {
    const DatasetFrame& frame = index.frames[i];
    const RawImage raw = readDatasetRawFrame(frame);
    if (raw.pixels.width() != source.width() || raw.pixels.height() != source.height())
      throw Error(frame.image_path + ": image is " + std::to_string(raw.pixels.width()) + "x" +
                  std::to_string(raw.pixels.height()) + ", expected " +
                  std::to_string(source.width()) + "x" + std::to_string(source.height()) +
                  " (" + frame.index_file + ":" + std::to_string(frame.index_line) + ")");
    ImageF image = photometric.correct(raw);
    if (rectification) image = remap(image, *rectification);
    return image;
  };
  auto request = [&](size_t i) {
    return std::async(options.prefetch ? std::launch::async : std::launch::deferred, load, i);
  };
  std::future<ImageF> next;
  if (total > 0) next = request(0);
  const auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < total; ++i) {
    const DatasetFrame& frame = index.frames[i];
    if (paced) {  // the camera's pace: frame i is due at (t_i − t_0) / speed after the start
      const double due_s = (frame.timestamp_s - index.frames[0].timestamp_s) / options.playback_speed;
      std::this_thread::sleep_until(start + std::chrono::duration<double>(due_s));
    }
    const ImageF image = next.get();  // rethrows a read error, naming the frame
    if (i + 1 < total) next = request(i + 1);
    // Exposure unknown (ASL layout): 1, so that only the affine model explains brightness.
    const double exposure = frame.exposure_ms > 0 ? frame.exposure_ms : 1.0;
    run.odometry->addFrame(image, frame.timestamp_s, exposure);
    if (options.progress) options.progress(i + 1, total, *run.odometry);
  }
  run.odometry->finish();  // the real-time mode's mapping thread catches up
  run.frames_processed = total;
  run.wall_s = wall.elapsedMs() / 1000.0;
  return run;
}

double viewWidthDeg(const DatasetIndex& index, const DatasetRunOptions& run) {
  const Camera source = synth::datasetCamera(index, run.calib);
  if (const std::optional<double> crop_fov = parsePinholeCrop(run.camera_model))
    return maximumViewAngleDeg(pinholeForFov(*crop_fov, source.width(), source.height()), Mask());
  const Mask content = run.detect_content ? detectSourceContent(index, source) : Mask();
  double width = maximumViewAngleDeg(source, content);  // the rays, with any distortion
  if (const std::optional<double> fov = parseNativeFov(run.camera_model))
    width = std::min(width, *fov);
  return width;
}

std::string applyIntrinsicsPrior(const DatasetIndex& index, const DatasetRunOptions& run,
                                 OdometryOptions* options) {
  return applyIntrinsicsPrior(viewWidthDeg(index, run), options);
}

std::string applyIntrinsicsPrior(double width, OdometryOptions* options) {
  if (width < kSelfCalibratingViewDeg || !options->window.optimize_intrinsics) return "";
  options->window.intrinsics_prior_weight = 0.0;
  std::ostringstream note;
  note << "a view " << std::fixed << std::setprecision(0) << width
       << "° wide (a hemisphere or more) observes the intrinsics: they are optimised without "
          "the calibration prior (--set window.intrinsics_prior_weight="
       << std::defaultfloat << WindowOptions{}.intrinsics_prior_weight << " holds them, as DSO does)";
  return note.str();
}

namespace {

// How the narrow view's notes begin: "a narrow view (109.5° across its widest, under 115°)".
std::string narrowViewLead(double view_width_deg) {
  std::ostringstream lead;
  lead << "a narrow view (" << std::fixed << std::setprecision(1) << view_width_deg
       << "° across its widest, under " << std::setprecision(0) << kNarrowViewBelowDeg << "°)";
  return lead.str();
}

}  // namespace

std::string applyViewProfile(double view_width_deg, bool exposure_times_known,
                             OdometryOptions* options) {
  if (view_width_deg >= kNarrowViewBelowDeg || !exposure_times_known) return "";
  const WindowOptions wide;
  options->window.central_difference_gradients = true;
  options->window.max_iterations = 3;
  std::ostringstream note;
  note << narrowViewLead(view_width_deg)
       << " with exposure times: the window solves on central-difference image gradients with "
       << options->window.max_iterations
       << " iterations, as DSO (--set window.central_difference_gradients="
       << (wide.central_difference_gradients ? "true" : "false")
       << " --set window.max_iterations=" << wide.max_iterations << " for a wide view's)";
  return note.str();
}

std::string applyNarrowViewTracking(double view_width_deg, OdometryOptions* options) {
  if (view_width_deg >= kNarrowViewBelowDeg) return "";
  constexpr int kNeighbours = 8;  // with τ's default 0.1 (reference_depth_consistency.hpp)
  options->reference_depths.neighbours = kNeighbours;
  std::ostringstream note;
  note << narrowViewLead(view_width_deg)
       << ": the tracker aligns only the reference points whose inverse distance agrees with "
          "their "
       << kNeighbours << " nearest neighbours' (--set reference_depths.neighbours="
       << ReferenceDepthConsistencyOptions{}.neighbours << " aligns every point)";
  return note.str();
}

}  // namespace omnidso::cli
