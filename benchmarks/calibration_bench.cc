// Calibration benchmarks on the real fisheye photos (../shared/data/fisheye_calibration_jy/
// left, 34 views 1280×800, 8×6 inner corners; OMNIDSO_DATA_DIR overrides the data root):
//   BM_DetectBoardCorners          corner detection in one image (read + SB detector)
//   BM_CalibrateModels/<models>    start, KB4 reference, outliers and the adjustment(s) of
//                                  the listed models on the 34 detected views (no files)
// Skipped with a message when the data is absent.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <omnidso/cameras/calibration/calibration.hpp>
#include <opencv2/imgcodecs.hpp>

namespace omnidso {
namespace {
namespace fs = std::filesystem;

const BoardSpec kBoard{8, 6, 1.0};

fs::path leftImages() {
  const char* env = std::getenv("OMNIDSO_DATA_DIR");
  return fs::path(env ? env : "../shared/data") / "fisheye_calibration_jy" / "left";
}

const BoardDetections* detections() {
  static const BoardDetections* cached = fs::is_directory(leftImages())
      ? new BoardDetections(detectBoardsInFolder(leftImages().string(), kBoard))
      : nullptr;
  return cached;
}

void BM_DetectBoardCorners(benchmark::State& state) {
  const fs::path image = leftImages() / "stereo_pair_000.jpg";
  if (!fs::exists(image)) return state.SkipWithError(("no " + image.string()).c_str());
  for (auto _ : state) {
    const cv::Mat grey = cv::imread(image.string(), cv::IMREAD_GRAYSCALE);
    benchmark::DoNotOptimize(detectBoardCorners(grey, kBoard));
  }
}
BENCHMARK(BM_DetectBoardCorners)->Unit(benchmark::kMillisecond);

void BM_CalibrateModels(benchmark::State& state, const std::string& models) {
  if (!detections()) return state.SkipWithError("fisheye_calibration_jy not found");
  for (auto _ : state)
    benchmark::DoNotOptimize(calibrateModels(*detections(), kBoard, parseModelList(models)));
}
BENCHMARK_CAPTURE(BM_CalibrateModels, kb4, std::string("kb4"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CalibrateModels, all_six,
                  std::string("ucm,eucm,ds,kb4,ucm-radtan,pinhole-radtan"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace omnidso
