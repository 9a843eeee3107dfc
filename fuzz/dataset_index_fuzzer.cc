// libFuzzer target for the dataset indices: TUM's times.txt and ASL's mav0/cam0/data.csv
// (OMNIDSO_FUZZ_DATASET_LAYOUT = 0 TUM, 1 ASL; fuzz/CMakeLists.txt). The fuzzed file is the
// index; the images it may name exist (4×3 PNGs 0, 1, 2 and 1403636579763555584), so that
// accepted indices go on to the timestamp checks and the first image's size.
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/image_io.hpp>

#include "fuzz_support.hpp"

namespace {

const char* const kImageNames[] = {"0", "1", "2", "1403636579763555584"};

// The dataset's directory with its images, made once per process.
std::string datasetRoot() {
  static const std::string root = [] {
    const std::filesystem::path dir = omnidso::fuzz::scratchDir() / "dataset";
    const std::filesystem::path images =
        OMNIDSO_FUZZ_DATASET_LAYOUT == 0 ? dir / "images" : dir / "mav0" / "cam0" / "data";
    std::filesystem::create_directories(images);
    const omnidso::ImageU8 image(4, 3, 128);
    for (const char* name : kImageNames) {
      omnidso::writeImage((images / (std::string(name) + ".png")).string(), image);
    }
    return dir.string();
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string root = datasetRoot();
  omnidso::fuzz::writeInput(
      OMNIDSO_FUZZ_DATASET_LAYOUT == 0 ? "dataset/times.txt" : "dataset/mav0/cam0/data.csv",
      data, size);
  return omnidso::fuzz::readOrRefuse([&] { omnidso::openDataset(root); });
}
