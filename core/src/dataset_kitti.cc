// The KITTI odometry layout: dataset/sequences/NN/ with times.txt (one timestamp per line),
// image_0/NNNNNN.png (the left grey camera, rectified) and calib.txt (P0..P3, Tr), and the
// ground truth of sequences 00–10 in dataset/poses/NN.txt. KITTI names images by the frame's
// position, so frame i (0-based, blank and '#' comment lines not counted) is
// image_0/<i, 6 digits>.png.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include <omnidso/core/error.hpp>

#include "dataset_detail.hpp"

namespace omnidso::dataset_detail {
namespace fs = std::filesystem;

namespace {

// dataset/poses/NN.txt for DIR = dataset/sequences/NN (or "dataset/sequences/NN/").
fs::path kittiPosesPath(const fs::path& sequence_dir) {
  fs::path normal = fs::absolute(sequence_dir).lexically_normal();
  if (!normal.has_filename()) normal = normal.parent_path();  // a trailing separator
  const std::string sequence_name = normal.filename().string();
  return normal.parent_path().parent_path() / "poses" / (sequence_name + ".txt");
}

}  // namespace

}  // namespace omnidso::dataset_detail

namespace omnidso {

std::vector<KittiTimestamp> readKittiTimes(const std::string& path) {
  std::ifstream times(path);
  if (!times) throw fileError(path, "missing: the KITTI layout lists its timestamps here");
  std::vector<KittiTimestamp> out;
  std::string line;
  int line_number = 0;
  while (std::getline(times, line)) {
    ++line_number;
    const std::vector<std::string> fields = dataset_detail::splitFields(line);
    if (fields.empty() || fields[0][0] == '#') continue;  // as in every text file read here
    if (fields.size() != 1) {
      throw fileError(path, line_number,
                      fmt::format("expected one timestamp in seconds (KITTI layout), got {} fields",
                                  fields.size()));
    }
    const double t = dataset_detail::parseNumber(fields[0], path, line_number, "timestamp");
    if (!std::isfinite(t)) throw fileError(path, line_number, "timestamp is not finite");
    out.push_back({t, line_number});
  }
  return out;
}

}  // namespace omnidso

namespace omnidso::dataset_detail {

LayoutIndex readKittiIndex(const std::string& root_path) {
  const fs::path root(root_path);
  const std::string times_path = (root / "times.txt").string();
  const fs::path images_dir = root / "image_0";

  LayoutIndex layout;
  DatasetIndex& index = layout.index;
  index.root = root_path;
  index.layout = DatasetLayout::kKitti;
  int frame_number = 0;
  for (const KittiTimestamp& stamp : readKittiTimes(times_path)) {
    DatasetFrame frame;
    frame.id = fmt::format("{:06d}", frame_number++);
    frame.timestamp_s = stamp.seconds;
    frame.exposure_ms = 0;  // KITTI records none
    frame.index_file = times_path;
    frame.index_line = stamp.line;
    frame.image_path = (images_dir / (frame.id + ".png")).string();
    if (fs::is_regular_file(frame.image_path)) {
      index.frames.push_back(std::move(frame));
    } else {
      layout.missing_images.push_back(std::move(frame));
    }
  }
  if (index.frames.empty() && layout.missing_images.empty()) {
    throw fileError(times_path, "empty: no frames listed");
  }

  index.calibration_paths.push_back((root / "calib.txt").string());
  if (const fs::path poses = kittiPosesPath(root); fs::is_regular_file(poses)) {
    index.groundtruth_path = poses.string();
    index.groundtruth_kind = GroundTruthKind::kCameraKitti;
  }
  return layout;
}

}  // namespace omnidso::dataset_detail
