#include <chrono>
#include <omnidso/cameras/rectification.hpp>
#include <thread>
#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/timing.hpp>
#include <omnidso/synth/dataset_loading.hpp>

namespace omnidso::cli {

std::optional<double> parsePinholeCrop(const std::string& text) {
  if (text == "native") return std::nullopt;
  const std::string prefix = "pinhole-crop:";
  if (text.rfind(prefix, 0) == 0) {
    try {
      size_t used = 0;
      const double fov = std::stod(text.substr(prefix.size()), &used);
      if (used == text.size() - prefix.size() && fov > 1.0 && fov < 179.0) return fov;
    } catch (const std::exception&) {
    }
  }
  throw Error("--camera-model: expected 'native' or 'pinhole-crop:FOV_DEG' with 1 < FOV < 179, got '" +
              text + "'");
}

DatasetRun runOdometryOnDataset(const DatasetIndex& index, const DatasetRunOptions& options) {
  const Camera source = synth::datasetCamera(index, options.calib);
  const std::optional<double> crop_fov = parsePinholeCrop(options.camera_model);
  // The odometry's camera, and the map from the raw images to it when they differ.
  Camera camera = source.undistortedModel();
  if (crop_fov) camera = pinholeForFov(*crop_fov, source.width(), source.height());
  std::optional<RectificationMap> rectification;
  Mask image_mask;
  if (crop_fov || source.hasDistortion()) {
    rectification = makeRectificationMap(source, camera);
    image_mask = validMask(*rectification);
  }
  const PhotometricCalibration photometric = PhotometricCalibration::fromFiles(
      index.pcalib_path.value_or(""), index.vignette_path.value_or(""));
  if (photometric.hasVignette()) photometric.checkImageSize(source.width(), source.height());

  DatasetRun run{source, camera, std::make_unique<Odometry>(camera, options.odometry, image_mask)};
  const size_t total = options.max_frames > 0 ? std::min(index.frames.size(), options.max_frames)
                                              : index.frames.size();
  Stopwatch wall;
  const bool paced = options.odometry.realtime && options.playback_speed > 0.0 && total > 0;
  const auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < total; ++i) {
    const DatasetFrame& frame = index.frames[i];
    if (paced) {  // the camera's pace: frame i is due at (t_i − t_0) / speed after the start
      const double due_s = (frame.timestamp_s - index.frames[0].timestamp_s) / options.playback_speed;
      std::this_thread::sleep_until(start + std::chrono::duration<double>(due_s));
    }
    RawImage raw;
    try {
      raw = readRawImage(frame.image_path);
    } catch (const Error& e) {  // point at the index line that lists the image too
      throw fileError(frame.index_file, frame.index_line, e.what());
    }
    if (raw.pixels.width() != source.width() || raw.pixels.height() != source.height())
      throw Error(frame.image_path + ": image is " + std::to_string(raw.pixels.width()) + "x" +
                  std::to_string(raw.pixels.height()) + ", expected " +
                  std::to_string(source.width()) + "x" + std::to_string(source.height()) +
                  " (" + frame.index_file + ":" + std::to_string(frame.index_line) + ")");
    ImageF image = photometric.correct(raw);
    if (rectification) image = remap(image, *rectification);
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

}  // namespace omnidso::cli
