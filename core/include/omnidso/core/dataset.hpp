#pragma once
// Dataset readers: an index of the frames of a sequence on disk, without decoding images.
//
// Three layouts (docs/architecture.md, ../shared/design.md):
// - TUM mono / omni: DIR/times.txt (lines `ID TIMESTAMP_S [EXPOSURE_MS]`, '#' comments),
//   DIR/images/ID.png|.jpg (ID of any width: the file name without extension), calibration
//   DIR/camchain.yaml (Kalibr) and/or DIR/camera.txt (DSO), optional DIR/pcalib.txt,
//   DIR/vignette.png and DIR/groundtruth.txt (TUM format, T_world_cam). Without it, TUM VI's
//   DSO folder (DIR = …/dso/cam0) takes the IMU's poses from …/dso/gt_imu.csv (ASL columns)
//   and lists …/dso/camchain.yaml (its T_cam_imu) after DIR's own calibration.
// - ASL (EuRoC, TUM VI): DIR/mav0/cam0/data.csv (`#timestamp [ns],filename`),
//   DIR/mav0/cam0/data/*.png, DIR/mav0/cam0/sensor.yaml, and ground truth of the BODY in
//   DIR/mav0/state_groundtruth_estimate0/data.csv (or mav0/mocap0/data.csv, or TUM VI's
//   dso/gt_imu.csv). The camera pose is T_world_body · T_BS; T_BS is in sensor.yaml (or,
//   as T_cam_imu⁻¹, in a Kalibr camchain), which the cameras library reads, so that
//   composition lives outside core (omnidso::synth::cameraGroundTruth).
//   TUM VI adds its DSO files beside mav0/: dso/camchain.yaml, dso/cam0/pcalib.txt,
//   dso/cam0/vignette.png, and exposure times in dso/cam0/times.txt (`ID_NS TIMESTAMP_S
//   EXPOSURE_MS`), taken when they cover every frame.
// Otherwise the ASL layout records no exposure time: exposure_ms is 0, meaning "unknown".
// - KITTI odometry (DIR = dataset/sequences/NN): DIR/times.txt (one timestamp in seconds per
//   line, nothing else), DIR/image_0/NNNNNN.png (frame i, 0-based over the timestamp lines of
//   times.txt, 6 digits; the left grey camera, rectified; image_1/ is ignored), DIR/calib.txt
//   (P0..P3 and Tr, 3×4 row-major; P0 holds image_0's pinhole, read by omnidso::cameras with
//   the images' size, which calib.txt lacks). Ground truth of sequences 00–10 in
//   DIR/../../poses/NN.txt: pose k (3×4 row-major T_world_cam) is frame k's, world = the
//   first frame's camera. No exposure times. Chosen when DIR has image_0/ and calib.txt but
//   no images/ (a TUM directory with a stray image_0/ stays TUM).
//
// Core does not parse calibration files (that needs omnidso::cameras): the index gives
// their paths. Bad datasets throw omnidso::Error naming the file and the line.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <omnidso/core/image.hpp>
#include <omnidso/core/image_io.hpp>

namespace omnidso {

enum class DatasetLayout { kTum, kAsl, kKitti };

const char* datasetLayoutName(DatasetLayout layout);  // "tum" | "asl" | "kitti"

// Which frame the ground-truth poses belong to.
enum class GroundTruthKind {
  kNone,
  kCameraTum,    // TUM text file `t tx ty tz qx qy qz qw`, T_world_cam
  kBodyAsl,      // ASL csv `t_ns, px, py, pz, qw, qx, qy, qz, ...`, T_world_body
  kCameraKitti,  // KITTI poses/NN.txt: a 3×4 T_world_cam per frame position, no timestamps
};

struct DatasetFrame {
  std::string id;          // image file name without extension, as written in the index
                           // (KITTI: the frame's position in times.txt, 6 digits)
  std::string image_path;  // absolute or relative to the working directory
  double timestamp_s = 0;
  double exposure_ms = 0;  // 0 = unknown (EuRoC's ASL records none)
  std::string index_file;  // times.txt or data.csv, and the line of this frame in it (1-based),
  int index_line = 0;      // so that errors about the image can point at both
};

struct DatasetIndex {
  std::string root;
  DatasetLayout layout = DatasetLayout::kTum;
  std::vector<DatasetFrame> frames;  // timestamps strictly increasing
  int width = 0;                     // of the first image
  int height = 0;
  std::vector<std::string> calibration_paths;  // existing files, preferred first
  std::optional<std::string> pcalib_path;
  std::optional<std::string> vignette_path;
  std::optional<std::string> groundtruth_path;
  GroundTruthKind groundtruth_kind = GroundTruthKind::kNone;
  // What the reader repaired (DatasetOpenOptions), "FILE: ..." — for the caller to show.
  std::vector<std::string> warnings;
};

struct DatasetOpenOptions {
  // Frames whose listed image is missing are dropped (with a warning) instead of refused.
  // Off by default: a copy interrupted at the end is the usual cause, and a run on fewer
  // frames than the user thinks gives numbers that are not comparable.
  bool skip_missing_images = false;
};

// Detects the layout (KITTI if DIR/image_0/ and DIR/calib.txt exist and DIR/images does
// not, else TUM if DIR/times.txt or DIR/images exists, ASL if DIR/mav0 exists),
// reads the frame list, checks that every listed image exists (one error naming the index
// file, the first missing frame's line and the missing images) and that timestamps
// increase, and reads the first image's size from its header.
DatasetIndex openDataset(const std::string& path, const DatasetOpenOptions& options = {});

// Width and height from the image file's header (PNG and JPEG parsed directly, and their
// end marker checked so that truncated files are caught without decoding; other formats
// decoded with OpenCV). Throws omnidso::Error when the file is unreadable or truncated.
struct ImageSize {
  int width = 0;
  int height = 0;
};
ImageSize readImageSize(const std::string& image_path);

// Reads every frame's image header and checks that all sizes equal the first image's:
// the one-second health check of `omnidso dataset info`. With decode, every image is also
// decoded (finds corruption inside a file; ~1–4 ms per frame).
void verifyDatasetImages(const DatasetIndex& index, bool decode = false);

// Decodes frame i as 8-bit grey (16-bit images are scaled by 1/257); throws when the
// image is unreadable or its size differs from the index's.
ImageU8 readDatasetFrame(const DatasetIndex& index, std::size_t i);

// The frame's image as stored (image_io.hpp, readRawImage); a read error names the index
// line that lists the image too.
RawImage readDatasetRawFrame(const DatasetFrame& frame);

// KITTI odometry's times.txt: one timestamp in seconds per line, blank and '#' lines skipped;
// the k-th timestamp is frame k's (and pose k's in poses/NN.txt). Throws omnidso::Error naming
// the file and line for a line of other than one number or a timestamp that is not finite.
struct KittiTimestamp {
  double seconds = 0;
  int line = 0;  // 1-based line in the file
};
std::vector<KittiTimestamp> readKittiTimes(const std::string& path);

// Time span (last − first timestamp) and mean frame rate (frames−1 over the span).
double datasetDuration(const DatasetIndex& index);
double datasetFrameRate(const DatasetIndex& index);

}  // namespace omnidso
