// libFuzzer target for the calibration readers: Kalibr camchain YAML, DSO camera.txt and
// EuRoC sensor.yaml, one executable per format (OMNIDSO_FUZZ_CALIBRATION, fuzz/CMakeLists.txt).
#include <omnidso/cameras/calibration_io.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace omnidso;
#if OMNIDSO_FUZZ_CALIBRATION == 0
  const std::string path = fuzz::writeInput("camchain.yaml", data, size);
  return fuzz::readOrRefuse([&] { loadKalibr(path); });
#elif OMNIDSO_FUZZ_CALIBRATION == 1
  const std::string path = fuzz::writeInput("camera.txt", data, size);
  return fuzz::readOrRefuse([&] { loadDsoCameraTxt(path); });
#else
  const std::string path = fuzz::writeInput("sensor.yaml", data, size);
  return fuzz::readOrRefuse([&] { loadEurocSensor(path); });
#endif
}
