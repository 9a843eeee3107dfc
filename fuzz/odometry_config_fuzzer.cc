// libFuzzer target for `omnidso run --config FILE` (a YAML map of odometry settings).
#include <omnidso/cli/odometry_settings.hpp>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = omnidso::fuzz::writeInput("config.yaml", data, size);
  return omnidso::fuzz::readOrRefuse([&] {
    omnidso::OdometryOptions options;
    omnidso::cli::applyOdometryConfigFile(options, path);
  });
}
