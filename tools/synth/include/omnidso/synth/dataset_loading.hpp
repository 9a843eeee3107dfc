#pragma once
// What a dataset index (omnidso/core/dataset.hpp) leaves to libraries above core: the
// camera from its calibration file, and the ground truth as camera poses. These need the
// cameras library (EuRoC's T_BS, Kalibr's T_cam_imu), which core must not depend on.

#include <string>

#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/se3.hpp>
#include <omnidso/core/trajectory.hpp>

namespace omnidso::synth {

// The camera from `override_path` if given, else from the dataset's first calibration
// file (any format loadCalibration detects, and KITTI's calib.txt, read at the images' size).
// Throws omnidso::Error when there is none, when the file is bad (unknown model, ...), or
// when its resolution differs from the images.
Camera datasetCamera(const DatasetIndex& index, const std::string& override_path = "");

// The camera's pose in the body whose poses an ASL ground truth holds: EuRoC's T_BS from
// mav0/cam0/sensor.yaml, else T_cam_imu⁻¹ from the first Kalibr camchain among the dataset's
// calibration files that has it (TUM VI: dso/camchain.yaml, with the IMU as the body).
// `source` is the file it came from. Throws omnidso::Error when there is neither.
struct BodyToCamera {
  SE3d T_body_camera;
  std::string source;
};
BodyToCamera bodyToCamera(const DatasetIndex& index);

// Ground truth as T_world_cam: TUM groundtruth.txt as stored; KITTI's poses/NN.txt (pose k
// is frame k's, no timestamps) as one pose per frame of the index at the frame's timestamp,
// frames dropped by --skip-missing keeping their own poses (more poses than frames is a clip,
// fine; fewer is an error naming the file and both counts); body poses (ASL csv, TUM VI's
// gt_imu.csv) composed with the camera's extrinsics (bodyToCamera), T_world_cam =
// T_world_body · T_BS, the file they came from written to `extrinsics_source` if given (left
// as it is for camera poses). Throws omnidso::Error if the dataset has no ground truth, or
// body poses and no extrinsics.
Trajectory cameraGroundTruth(const DatasetIndex& index, std::string* extrinsics_source = nullptr);

}  // namespace omnidso::synth
