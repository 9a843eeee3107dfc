// Camera and camera-frame ground truth of a dataset (dataset_loading.hpp).
#include <omnidso/synth/dataset_loading.hpp>

#include <charconv>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/trajectory_io.hpp>

namespace omnidso::synth {

Camera datasetCamera(const DatasetIndex& index, const std::string& override_path) {
  std::string path = override_path;
  if (path.empty()) {
    if (index.calibration_paths.empty()) {
      throw fileError(index.root,
                      "no calibration file (camchain.yaml, camera.txt or mav0/cam0/sensor.yaml); "
                      "pass one with --calib");
    }
    path = index.calibration_paths.front();
  }
  // KITTI's calib.txt has no image size: the images give it, so it always fits them.
  if (detectCalibrationFormat(path) == CalibrationFormat::kKittiCalib) {
    return loadKittiCalib(path, index.width, index.height);
  }
  const Camera camera = loadCalibration(path);
  if (camera.width() != index.width || camera.height() != index.height) {
    throw fileError(path, fmt::format("calibration is for {}x{} images, the dataset's are {}x{}",
                                      camera.width(), camera.height(), index.width,
                                      index.height));
  }
  return camera;
}

BodyToCamera bodyToCamera(const DatasetIndex& index) {
  for (const std::string& path : index.calibration_paths) {
    if (std::filesystem::path(path).filename() == "sensor.yaml")
      return {loadEurocSensor(path).T_body_sensor, path};
  }
  for (const std::string& path : index.calibration_paths) {
    if (detectCalibrationFormat(path) != CalibrationFormat::kKalibr) continue;
    if (const std::optional<SE3d> cam_imu = loadKalibrCamImu(path))
      return {cam_imu->inverse(), path};
  }
  throw fileError(index.groundtruth_path.value_or(index.root),
                  "body-frame ground truth needs the camera's extrinsics: T_BS in "
                  "mav0/cam0/sensor.yaml or T_cam_imu in a Kalibr camchain.yaml; neither found");
}

namespace {

// The KITTI layout's frame id is the frame's position in times.txt ("000042" → 42).
std::size_t kittiFramePosition(const DatasetFrame& frame) {
  std::size_t position = 0;
  const char* end = frame.id.data() + frame.id.size();
  const auto [ptr, ec] = std::from_chars(frame.id.data(), end, position);
  if (ec != std::errc() || ptr != end || frame.id.empty()) {
    throw fileError(frame.index_file, frame.index_line,
                    fmt::format("frame id '{}' is not a KITTI frame number", frame.id));
  }
  return position;
}

// KITTI's poses/NN.txt holds one pose per frame position, without timestamps (the reader
// stamps pose k with k). Each frame takes the pose of its position, so that it keeps its own
// when --skip-missing dropped others before it (or a comment line shifted times.txt's lines),
// at the frame's timestamp, which the evaluation associates by.
Trajectory kittiGroundTruth(const DatasetIndex& index) {
  const std::string& path = *index.groundtruth_path;
  const Trajectory by_position = readTrajectory(path, TrajectoryFormat::kKitti);
  Trajectory poses;
  poses.reserve(index.frames.size());
  for (const DatasetFrame& frame : index.frames) {
    const std::size_t position = kittiFramePosition(frame);
    if (position >= by_position.size()) {
      const std::size_t needed = kittiFramePosition(index.frames.back()) + 1;
      throw fileError(path, fmt::format("{} poses, but the frames need {}: the first without one "
                                        "is frame {} ({}:{})",
                                        by_position.size(), needed, frame.id, frame.index_file,
                                        frame.index_line));
    }
    poses.push_back({frame.timestamp_s, by_position[position].pose});
  }
  return poses;
}

}  // namespace

Trajectory cameraGroundTruth(const DatasetIndex& index, std::string* extrinsics_source) {
  if (!index.groundtruth_path) throw fileError(index.root, "dataset has no ground truth");
  if (index.groundtruth_kind == GroundTruthKind::kCameraTum) {
    return readTrajectoryTum(*index.groundtruth_path);
  }
  if (index.groundtruth_kind == GroundTruthKind::kCameraKitti) return kittiGroundTruth(index);
  Trajectory body = readTrajectory(*index.groundtruth_path, TrajectoryFormat::kEuroc);
  const BodyToCamera extrinsics = bodyToCamera(index);
  if (extrinsics_source) *extrinsics_source = extrinsics.source;
  for (StampedPose& pose : body) pose.pose = pose.pose * extrinsics.T_body_camera;
  return body;
}

}  // namespace omnidso::synth
