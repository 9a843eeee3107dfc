// libFuzzer target for DSO's pcalib.txt (the inverse response G⁻¹, 256 numbers).
#include <omnidso/core/photometric_calibration.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = omnidso::fuzz::writeInput("pcalib.txt", data, size);
  return omnidso::fuzz::readOrRefuse([&] { omnidso::readPcalib(path); });
}
