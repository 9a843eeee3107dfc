#pragma once
// What a dataset index (omnidso/core/dataset.hpp) leaves to libraries above core: the
// camera from its calibration file, and the ground truth as camera poses. These need the
// cameras library (T_BS of EuRoC's sensor.yaml), which core must not depend on.

#include <string>

#include <omnidso/cameras/camera.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/trajectory.hpp>

namespace omnidso::synth {

// The camera from `override_path` if given, else from the dataset's first calibration
// file (any format loadCalibration detects). Throws omnidso::Error when there is none,
// when the file is bad (unknown model, ...), or when its resolution differs from the images.
Camera datasetCamera(const DatasetIndex& index, const std::string& override_path = "");

// Ground truth as T_world_cam: TUM groundtruth.txt as stored; ASL body poses composed with
// the camera's extrinsics, T_world_cam = T_world_body · T_BS (T_BS from sensor.yaml).
// Throws omnidso::Error if the dataset has no ground truth.
Trajectory cameraGroundTruth(const DatasetIndex& index);

}  // namespace omnidso::synth
