// The TUM-layout dataset writer (dataset_writer.hpp).
#include <omnidso/synth/dataset_writer.hpp>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/image_io.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/trajectory_io.hpp>

namespace omnidso::synth {
namespace fs = std::filesystem;

std::string frameId(int index, int num_frames) {
  int width = 5;
  for (int capacity = 100000; num_frames > capacity; capacity *= 10) ++width;
  return fmt::format("{:0{}d}", index, width);
}

namespace {

const char* const kDatasetFiles[] = {"times.txt",  "camchain.yaml", "camera.txt",
                                     "pcalib.txt", "vignette.png",  "groundtruth.txt"};

void prepareDirectory(const fs::path& dir, bool overwrite) {
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw fileError(dir.string(), "exists and is not a directory");
  }
  if (fs::exists(dir) && !fs::is_empty(dir)) {
    if (!overwrite) {
      throw fileError(dir.string(), "output directory is not empty (use --force to overwrite)");
    }
    fs::remove_all(dir / "images");
    for (const char* file : kDatasetFiles) fs::remove(dir / file);
  }
  std::error_code error;
  fs::create_directories(dir / "images", error);
  if (error) throw fileError(dir.string(), "cannot create: " + error.message());
}

}  // namespace

void writeSyntheticDataset(SyntheticSequence& sequence, const std::string& out_dir,
                           const DatasetWriteOptions& options) {
  const fs::path dir(out_dir);
  prepareDirectory(dir, options.overwrite);

  const Camera& camera = sequence.camera();
  saveKalibr((dir / "camchain.yaml").string(), camera);
  try {
    saveDsoCameraTxt((dir / "camera.txt").string(), camera);
  } catch (const Error&) {
    fs::remove(dir / "camera.txt");  // DSO has no such model: camchain.yaml alone
  }
  writePcalib((dir / "pcalib.txt").string(), sequence.renderer().photometric().inverseResponseTable());
  writeVignette((dir / "vignette.png").string(), sequence.renderer().vignette());
  writeTrajectoryTum((dir / "groundtruth.txt").string(), sequence.groundTruth());

  const std::string times_path = (dir / "times.txt").string();
  std::ofstream times(times_path);
  if (!times) throw fileError(times_path, "cannot be written");
  times << "# id timestamp_s exposure_ms\n";
  const int total = sequence.numFrames();
  while (sequence.hasNext()) {
    const SyntheticSequence::Frame frame = sequence.renderNext();
    const std::string id = frameId(frame.index, total);
    writeImage((dir / "images" / (id + ".png")).string(), frame.image);
    // {} prints the shortest decimal that reads back as the same double.
    times << fmt::format("{} {} {}\n", id, frame.timestamp_s, frame.exposure_ms);
    if (options.progress) options.progress(frame.index + 1, total);
  }
  times.flush();
  if (!times) throw fileError(times_path, "write failed");
}

}  // namespace omnidso::synth
