#pragma once
// Inputs of the bad-input corpus (bad_input_corpus_test.cc): two small valid datasets that
// each case copies and then breaks — a rendered TUM-layout sequence (3 frames of 96×96 with
// calibration, pcalib, vignette and ground truth) and an ASL-layout one with the same images
// — and byte helpers. Built once per test process, in a temporary directory removed at exit.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/synth/dataset_writer.hpp>

#include "synth_test_util.hpp"

namespace omnidso::test {

inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

inline void writeGreyPng(const std::filesystem::path& path, int width, int height, int value) {
  cv::imwrite(path.string(), cv::Mat(height, width, CV_8UC1, cv::Scalar(value)));
}

// 600 bytes of every value (NUL, newlines, high bytes included), the same for a seed.
inline std::string garbage(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::string bytes(600, '\0');
  for (char& c : bytes) c = static_cast<char>(byte(rng));
  return bytes;
}

class BadInputFixtures {
 public:
  static const BadInputFixtures& get() {
    static const BadInputFixtures fixtures;
    return fixtures;
  }
  ~BadInputFixtures() {
    std::error_code ignored;
    std::filesystem::remove_all(root_, ignored);
  }

  // A fresh directory for one test's cases.
  std::filesystem::path caseRoot(const std::string& test_name) const {
    const std::filesystem::path dir = root_ / "cases" / test_name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
  }
  void copyTumDataset(const std::filesystem::path& to) const { copyTree(root_ / "tum", to); }
  void copyAslDataset(const std::filesystem::path& to) const { copyTree(root_ / "asl", to); }

 private:
  BadInputFixtures()
      : root_(std::filesystem::temp_directory_path() /
              ("omnidso_bad_input_" + std::to_string(::getpid()))) {
    namespace fs = std::filesystem;
    fs::remove_all(root_);
    synth::SyntheticSequence sequence(smallSequenceConfig(3));
    synth::writeSyntheticDataset(sequence, (root_ / "tum").string());
    // ASL: the same three images under nanosecond names, a pinhole sensor.yaml.
    const fs::path cam = root_ / "asl" / "mav0" / "cam0";
    fs::create_directories(cam / "data");
    std::string csv = "#timestamp [ns],filename\n";
    for (int i = 0; i < 3; ++i) {
      const std::string name = std::to_string(1000000000 + 50000000 * i) + ".png";
      fs::copy_file(root_ / "tum" / "images" / ("0000" + std::to_string(i) + ".png"),
                    cam / "data" / name);
      csv += name.substr(0, name.size() - 4) + "," + name + "\n";
    }
    writeBytes(cam / "data.csv", csv);
    writeBytes(cam / "sensor.yaml",
               "%YAML:1.0\ncamera_model: pinhole\nintrinsics: [40, 40, 47.5, 47.5]\n"
               "distortion_model: radial-tangential\n"
               "distortion_coefficients: [0.01, 0.0, 0.0, 0.0]\nresolution: [96, 96]\n"
               "T_BS:\n  rows: 4\n  cols: 4\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, "
               "0, 1]\n");
  }

  static void copyTree(const std::filesystem::path& from, const std::filesystem::path& to) {
    std::filesystem::create_directories(to.parent_path());
    std::filesystem::copy(from, to, std::filesystem::copy_options::recursive);
  }

  std::filesystem::path root_;
};

}  // namespace omnidso::test
