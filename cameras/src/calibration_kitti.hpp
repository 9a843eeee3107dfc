#pragma once
// Internal to the calibration readers: how a KITTI calib.txt is told from DSO's camera.txt
// (both are .txt), shared by the detection (calibration_io.cc) and the reader
// (calibration_kitti.cc) so that they agree on which line holds image_0's projection.

#include <string>

namespace omnidso::detail {

// True for a line `P0: ...` (leading blanks allowed): KITTI's projection of image_0.
bool isKittiP0Line(const std::string& line);

}  // namespace omnidso::detail
