// The ASL layout of EuRoC and TUM VI: mav0/cam0/data.csv + mav0/cam0/data/*.png, and TUM VI's
// DSO files in dso/ (calibration, response, vignette, exposure times).
#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include <omnidso/core/error.hpp>

#include "dataset_detail.hpp"

namespace omnidso::dataset_detail {
namespace fs = std::filesystem;

namespace {

// TUM VI records each frame's exposure in the DSO files beside mav0/: dso/cam0/times.txt,
// lines `ID_NS TIMESTAMP_S EXPOSURE_MS`, ID the image's file name without extension. Taken
// only when it covers every listed frame: frames without one would be read at exposure 1,
// a brightness model with a silently wrong gain (a warning says why they were not taken).
void readDsoExposures(const fs::path& path, LayoutIndex* layout) {
  // fs::exists throws on a symbolic-link loop (openDataset reports it); a file that is there
  // but cannot be read is an error too, not a silent run without exposure times.
  if (!fs::exists(path)) return;
  const std::string times_path = path.string();
  std::ifstream times(times_path);
  if (!times) throw fileError(times_path, "cannot open exposure times file");
  std::map<std::string, double> exposure_by_id;
  std::string line;
  int line_number = 0;
  while (std::getline(times, line)) {
    ++line_number;
    const std::optional<TimesLine> parsed = parseTimesLine(line, times_path, line_number);
    if (!parsed || parsed->exposure_ms == 0) continue;  // no exposure for this frame
    exposure_by_id[parsed->id] = parsed->exposure_ms;
  }
  if (exposure_by_id.empty()) return;  // a file without the exposure column
  std::vector<DatasetFrame>& frames = layout->index.frames;
  const auto uncovered = std::count_if(frames.begin(), frames.end(), [&](const DatasetFrame& f) {
    return exposure_by_id.count(f.id) == 0;
  });
  if (uncovered > 0) {
    layout->index.warnings.push_back(fmt::format(
        "{}: exposure times not used: {} of the {} frames of mav0/cam0/data.csv have none there",
        times_path, uncovered, frames.size()));
    return;
  }
  for (DatasetFrame& frame : frames) frame.exposure_ms = exposure_by_id.at(frame.id);
}

}  // namespace

LayoutIndex readAslIndex(const std::string& root_path) {
  const fs::path root(root_path);
  const fs::path cam_dir = root / "mav0" / "cam0";
  const std::string csv_path = (cam_dir / "data.csv").string();
  std::ifstream csv(csv_path);
  if (!csv) throw fileError(csv_path, "missing: the ASL layout lists its frames here");

  LayoutIndex layout;
  DatasetIndex& index = layout.index;
  index.root = root_path;
  index.layout = DatasetLayout::kAsl;
  std::string line;
  int line_number = 0;
  while (std::getline(csv, line)) {
    ++line_number;
    const std::vector<std::string> fields = splitFields(line);
    if (fields.empty() || fields[0][0] == '#') continue;
    if (fields.size() != 2) {
      throw fileError(csv_path, line_number,
                      fmt::format("expected 'TIMESTAMP_NS,FILENAME', got {} fields",
                                  fields.size()));
    }
    DatasetFrame frame;
    // Nanoseconds since the epoch: ~1.4e18 exceeds double's 2^53 integer range, so split
    // into seconds and the remainder before converting (keeps sub-microsecond accuracy).
    // from_chars, not stoll: 19 digits may exceed int64 (found by fuzzing, fuzz/).
    const std::string& stamp = fields[0];
    long long ns = 0;
    const auto [end, status] = std::from_chars(stamp.data(), stamp.data() + stamp.size(), ns);
    if (stamp.find_first_not_of("0123456789") != std::string::npos ||
        status != std::errc() || end != stamp.data() + stamp.size()) {
      throw fileError(csv_path, line_number,
                      fmt::format("timestamp '{}' is not an integer in nanoseconds", stamp));
    }
    frame.timestamp_s = static_cast<double>(ns / 1000000000LL) +
                        static_cast<double>(ns % 1000000000LL) * 1e-9;
    frame.exposure_ms = 0.0;  // unknown unless TUM VI's dso/cam0/times.txt gives it
    frame.id = fs::path(fields[1]).stem().string();
    const fs::path image = cam_dir / "data" / fields[1];
    frame.image_path = image.string();
    frame.index_file = csv_path;
    frame.index_line = line_number;
    (fs::is_regular_file(image) ? index.frames : layout.missing_images).push_back(std::move(frame));
  }
  if (index.frames.empty() && layout.missing_images.empty()) {
    throw fileError(csv_path, "empty: no frames listed");
  }

  if (fs::is_regular_file(cam_dir / "sensor.yaml")) {
    index.calibration_paths.push_back((cam_dir / "sensor.yaml").string());
  }
  // TUM VI ships Kalibr/DSO calibrations next to mav0/ in its "dso" folder.
  for (const fs::path& extra : {root / "camchain.yaml", root / "dso" / "camchain.yaml",
                                root / "camera.txt", root / "dso" / "camera.txt"}) {
    if (fs::is_regular_file(extra)) index.calibration_paths.push_back(extra.string());
  }
  for (const fs::path& photometric :
       {root / "pcalib.txt", root / "dso" / "cam0" / "pcalib.txt", root / "dso" / "pcalib.txt"}) {
    if (!index.pcalib_path && fs::is_regular_file(photometric)) {
      index.pcalib_path = photometric.string();
    }
  }
  for (const fs::path& vignette : {root / "vignette.png", root / "dso" / "cam0" / "vignette.png",
                                   root / "dso" / "vignette.png"}) {
    if (!index.vignette_path && fs::is_regular_file(vignette)) {
      index.vignette_path = vignette.string();
    }
  }
  readDsoExposures(root / "dso" / "cam0" / "times.txt", &layout);
  for (const fs::path& gt : {root / "mav0" / "state_groundtruth_estimate0" / "data.csv",
                             root / "mav0" / "mocap0" / "data.csv", root / "dso" / "gt_imu.csv"}) {
    if (fs::is_regular_file(gt)) {
      index.groundtruth_path = gt.string();
      index.groundtruth_kind = GroundTruthKind::kBodyAsl;
      break;
    }
  }
  return layout;
}

}  // namespace omnidso::dataset_detail
