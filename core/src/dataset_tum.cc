// The TUM mono / omni layout: times.txt + images/ID.(png|jpg).
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include <omnidso/core/error.hpp>

#include "dataset_detail.hpp"

namespace omnidso::dataset_detail {
namespace fs = std::filesystem;

namespace {

bool isImageExtension(const std::string& ext) {
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".PNG" || ext == ".JPG";
}

// File stem → path of every image in images/, listed once so that a lookup per frame is
// a map search, not a file-system call per extension.
std::map<std::string, std::string> listImages(const fs::path& dir) {
  std::map<std::string, std::string> images;
  if (!fs::is_directory(dir)) return images;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    // An entry whose type cannot be read (a symbolic-link loop) is listed: reading it then
    // fails with an error at its line in times.txt.
    std::error_code unreadable;
    const bool regular = entry.is_regular_file(unreadable);
    if ((!regular && !unreadable) || !isImageExtension(entry.path().extension().string())) {
      continue;
    }
    images.emplace(entry.path().stem().string(), entry.path().string());
  }
  return images;
}

void addIfExists(const fs::path& file, std::optional<std::string>& out) {
  if (fs::is_regular_file(file)) out = file.string();
}

// The folder holding `dir` ("a/dso" for "a/dso/cam0" or "a/dso/cam0/").
fs::path containingFolder(const fs::path& dir) {
  fs::path normal = fs::absolute(dir).lexically_normal();
  if (!normal.has_filename()) normal = normal.parent_path();  // a trailing separator
  return normal.parent_path();
}

}  // namespace

LayoutIndex readTumIndex(const std::string& root_path) {
  const fs::path root(root_path);
  const std::string times_path = (root / "times.txt").string();
  std::ifstream times(times_path);
  if (!times) throw fileError(times_path, "missing: the TUM layout lists its frames here");
  const fs::path images_dir = root / "images";
  if (!fs::is_directory(images_dir)) {
    throw fileError(images_dir.string(), "missing: the TUM layout keeps its frames here");
  }
  const std::map<std::string, std::string> images = listImages(images_dir);

  LayoutIndex layout;
  DatasetIndex& index = layout.index;
  index.root = root_path;
  index.layout = DatasetLayout::kTum;
  std::string line;
  int line_number = 0;
  while (std::getline(times, line)) {
    ++line_number;
    const std::optional<TimesLine> parsed = parseTimesLine(line, times_path, line_number);
    if (!parsed) continue;
    DatasetFrame frame;
    frame.id = parsed->id;
    frame.timestamp_s = parsed->timestamp_s;
    frame.exposure_ms = parsed->exposure_ms;
    frame.index_file = times_path;
    frame.index_line = line_number;
    const auto image = images.find(frame.id);
    if (image == images.end()) {
      frame.image_path = (images_dir / frame.id).string() + ".png|.jpg";
      layout.missing_images.push_back(std::move(frame));
      continue;
    }
    frame.image_path = image->second;
    index.frames.push_back(std::move(frame));
  }
  if (index.frames.empty() && layout.missing_images.empty()) {
    throw fileError(times_path, "empty: no frames listed");
  }

  for (const char* name : {"camchain.yaml", "camera.txt"}) {
    if (fs::is_regular_file(root / name)) index.calibration_paths.push_back((root / name).string());
  }
  addIfExists(root / "pcalib.txt", index.pcalib_path);
  addIfExists(root / "vignette.png", index.vignette_path);
  addIfExists(root / "groundtruth.txt", index.groundtruth_path);
  if (index.groundtruth_path) {
    index.groundtruth_kind = GroundTruthKind::kCameraTum;
  } else if (const fs::path dso = containingFolder(root);
             dso.filename() == "dso" && fs::is_regular_file(dso / "gt_imu.csv")) {
    // TUM VI's DSO folder, dso/cam0: the IMU's poses in dso/gt_imu.csv (ASL columns), the
    // camera–IMU extrinsics in dso/camchain.yaml (added after this folder's own calibration).
    index.groundtruth_path = (dso / "gt_imu.csv").string();
    index.groundtruth_kind = GroundTruthKind::kBodyAsl;
    if (fs::is_regular_file(dso / "camchain.yaml"))
      index.calibration_paths.push_back((dso / "camchain.yaml").string());
  }
  return layout;
}

}  // namespace omnidso::dataset_detail
