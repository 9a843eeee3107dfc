// libFuzzer target for the trajectory readers, one executable per format
// (OMNIDSO_FUZZ_TRAJECTORY_FORMAT = 0 TUM, 1 KITTI, 2 EuRoC; fuzz/CMakeLists.txt).
#include <omnidso/core/trajectory_io.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace omnidso;
  constexpr TrajectoryFormat kFormat = static_cast<TrajectoryFormat>(OMNIDSO_FUZZ_TRAJECTORY_FORMAT);
  const std::string path = fuzz::writeInput("trajectory.txt", data, size);
  return fuzz::readOrRefuse([&] { readTrajectory(path, kFormat); });
}
