#pragma once
// Helpers shared by the synthetic-data tests: a temporary directory and a small, fast
// sequence configuration (tiny images, coarse textures, few frames).

#include <unistd.h>

#include <filesystem>
#include <string>

#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso::test {

class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("omnidso_synth_test_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// 96×96 UCM at 185°, 2 cm texels, a handful of frames: renders in milliseconds.
inline synth::SyntheticSequenceConfig smallSequenceConfig(int frames = 4, std::uint64_t seed = 5) {
  synth::SyntheticSequenceConfig config = synth::presetConfig("room185");
  config.width = 96;
  config.height = 96;
  config.frames = frames;
  config.seed = seed;
  config.room.texel_size = 0.02;
  return config;
}

}  // namespace omnidso::test
