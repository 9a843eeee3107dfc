// The dataset readers: TUM mono/omni, ASL and KITTI odometry layouts, and each bad-dataset
// error.
#include <omnidso/core/dataset.hpp>

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/core/error.hpp>

#include "test_data.hpp"

namespace omnidso {
namespace {
namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("omnidso_dataset_test_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

void writeText(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
}

void writeGreyImage(const fs::path& file, int width, int height, int value) {
  cv::imwrite(file.string(), cv::Mat(height, width, CV_8UC1, cv::Scalar(value)));
}

// A TUM-layout dataset of three 16×12 frames with IDs of width 3 and mixed extensions.
void writeTumDataset(const fs::path& dir) {
  fs::create_directories(dir / "images");
  writeGreyImage(dir / "images" / "000.png", 16, 12, 10);
  writeGreyImage(dir / "images" / "001.jpg", 16, 12, 20);
  writeGreyImage(dir / "images" / "002.png", 16, 12, 30);
  writeText(dir / "times.txt",
            "# id t exposure\n000 1.0 10.5\n001 1.05 11.0\n\n002 1.1 11.5\n");
}

// Runs openDataset + verifyDatasetImages and returns the error message ("" if none).
std::string openError(const fs::path& dir) {
  try {
    verifyDatasetImages(openDataset(dir.string()));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(DatasetTest, ReadsTumLayoutWithAnyIdWidthAndExtension) {
  TempDir tmp("tum");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "camchain.yaml", "cam0: {}\n");
  writeText(tmp.path() / "pcalib.txt", "0 1 2\n");
  const DatasetIndex index = openDataset(tmp.path().string());
  EXPECT_EQ(index.layout, DatasetLayout::kTum);
  ASSERT_EQ(index.frames.size(), 3u);
  EXPECT_EQ(index.frames[1].id, "001");
  EXPECT_EQ(fs::path(index.frames[1].image_path).extension(), ".jpg");
  EXPECT_DOUBLE_EQ(index.frames[2].timestamp_s, 1.1);
  EXPECT_DOUBLE_EQ(index.frames[2].exposure_ms, 11.5);
  EXPECT_EQ(index.frames[2].index_line, 5);
  EXPECT_EQ(index.width, 16);
  EXPECT_EQ(index.height, 12);
  ASSERT_EQ(index.calibration_paths.size(), 1u);
  EXPECT_TRUE(index.pcalib_path.has_value());
  EXPECT_FALSE(index.vignette_path.has_value());
  EXPECT_EQ(index.groundtruth_kind, GroundTruthKind::kNone);
  EXPECT_NO_THROW(verifyDatasetImages(index));
  // JPEG is lossy, but a constant image stays within a grey level of its value.
  EXPECT_NEAR(readDatasetFrame(index, 1)(5, 5), 20, 1);
  EXPECT_EQ(readDatasetFrame(index, 2)(0, 0), 30);
  EXPECT_NEAR(datasetFrameRate(index), 20.0, 1e-9);
}

TEST(DatasetTest, ReadsImageSizeFromPngAndJpegHeaders) {
  TempDir tmp("size");
  writeGreyImage(tmp.path() / "a.png", 37, 21, 0);
  writeGreyImage(tmp.path() / "b.jpg", 45, 19, 0);
  EXPECT_EQ(readImageSize((tmp.path() / "a.png").string()).width, 37);
  EXPECT_EQ(readImageSize((tmp.path() / "a.png").string()).height, 21);
  EXPECT_EQ(readImageSize((tmp.path() / "b.jpg").string()).width, 45);
  EXPECT_EQ(readImageSize((tmp.path() / "b.jpg").string()).height, 19);
}

TEST(DatasetTest, RejectsMissingTimesFile) {
  TempDir tmp("no_times");
  writeTumDataset(tmp.path());
  fs::remove(tmp.path() / "times.txt");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt: missing"), std::string::npos) << error;
}

TEST(DatasetTest, RejectsEmptyTimesFile) {
  TempDir tmp("empty_times");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "times.txt", "# nothing\n");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt: empty"), std::string::npos) << error;
}

TEST(DatasetTest, RejectsTimestampWithoutImage) {
  TempDir tmp("missing_image");
  writeTumDataset(tmp.path());
  fs::remove(tmp.path() / "images" / "002.png");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:5: image '"), std::string::npos) << error;
  EXPECT_NE(error.find("002.png|.jpg' not found"), std::string::npos) << error;
}

// The end of a copy interrupted: every missing image is named, at the first one's line;
// skipping drops them with a warning, and a missing image in the middle is dropped too.
TEST(DatasetTest, MissingImagesAreNamedOrSkipped) {
  TempDir tmp("missing_at_end");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "times.txt",
            "000 1.0\n001 1.05\n002 1.1\n003 1.15\n004 1.2\n# end\n");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:4: 2 listed images not found at the end of the list"),
            std::string::npos) << error;
  EXPECT_NE(error.find("003.png|.jpg (line 4), "), std::string::npos) << error;
  EXPECT_NE(error.find("004.png|.jpg (line 5)"), std::string::npos) << error;

  DatasetOpenOptions skip;
  skip.skip_missing_images = true;
  DatasetIndex index = openDataset(tmp.path().string(), skip);
  ASSERT_EQ(index.frames.size(), 3u);
  EXPECT_EQ(index.frames[2].id, "002");
  EXPECT_EQ(index.frames[0].exposure_ms, 0.0);  // no exposure column: unknown
  ASSERT_EQ(index.warnings.size(), 1u);
  EXPECT_NE(index.warnings[0].find("2 frame(s) dropped"), std::string::npos) << index.warnings[0];

  fs::remove(tmp.path() / "images" / "001.jpg");
  index = openDataset(tmp.path().string(), skip);
  ASSERT_EQ(index.frames.size(), 2u);
  EXPECT_EQ(index.frames[1].id, "002");
  EXPECT_NE(openError(tmp.path()).find("times.txt:2: 3 listed images not found: "),
            std::string::npos) << openError(tmp.path());
}

TEST(DatasetTest, RejectsTimestampsNotIncreasing) {
  TempDir tmp("order");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "times.txt", "000 1.0 10\n001 1.05 10\n002 1.05 10\n");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:3: timestamp"), std::string::npos) << error;
}

TEST(DatasetTest, RejectsMalformedLine) {
  TempDir tmp("malformed");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "times.txt", "000 1.0 10\n001 one 10\n");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:2: timestamp 'one' is not a number"), std::string::npos)
      << error;
}

TEST(DatasetTest, RejectsWrongSizeImage) {
  TempDir tmp("wrong_size");
  writeTumDataset(tmp.path());
  writeGreyImage(tmp.path() / "images" / "002.png", 15, 12, 0);
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:5: image"), std::string::npos) << error;
  EXPECT_NE(error.find("is 15x12, but the first image is 16x12"), std::string::npos) << error;
}

TEST(DatasetTest, RejectsUnreadableImage) {
  TempDir tmp("unreadable");
  writeTumDataset(tmp.path());
  writeText(tmp.path() / "images" / "001.jpg", "not an image");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:3:"), std::string::npos) << error;
  EXPECT_NE(error.find("unreadable"), std::string::npos) << error;
}

TEST(DatasetTest, RejectsTruncatedImagesFromTheirHeadersAlone) {
  TempDir tmp("truncated");
  writeTumDataset(tmp.path());
  for (const char* name : {"002.png", "001.jpg"}) {
    const fs::path image = tmp.path() / "images" / name;
    const auto full_size = fs::file_size(image);
    fs::resize_file(image, full_size - 8);
    const std::string error = openError(tmp.path());
    EXPECT_NE(error.find("truncated"), std::string::npos) << name << ": " << error;
    writeTumDataset(tmp.path());
  }
}

TEST(DatasetTest, DecodingFindsCorruptPixelData) {
  TempDir tmp("corrupt");
  writeTumDataset(tmp.path());
  // Overwrite the middle of the PNG (its compressed pixel data) but keep header and IEND.
  const fs::path image = tmp.path() / "images" / "002.png";
  {
    std::fstream file(image, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(40);
    file.write("garbagegarbage", 14);
  }
  const DatasetIndex index = openDataset(tmp.path().string());
  EXPECT_NO_THROW(verifyDatasetImages(index));  // the header is intact
  EXPECT_THROW(verifyDatasetImages(index, /*decode=*/true), Error);
}

TEST(DatasetTest, RejectsDirectoryThatIsNoDataset) {
  TempDir tmp("nothing");
  EXPECT_NE(openError(tmp.path()).find("not a dataset"), std::string::npos);
  EXPECT_NE(openError(tmp.path() / "absent").find("not found"), std::string::npos);
}

// An ASL dataset (mav0/cam0) of 8×6 frames named by their nanosecond timestamps.
void writeAslFrames(const fs::path& root, const std::vector<std::string>& stamps_ns) {
  const fs::path cam = root / "mav0" / "cam0";
  fs::create_directories(cam / "data");
  std::string csv = "#timestamp [ns],filename\n";
  for (size_t i = 0; i < stamps_ns.size(); ++i) {
    writeGreyImage(cam / "data" / (stamps_ns[i] + ".png"), 8, 6, static_cast<int>(i + 1));
    csv += stamps_ns[i] + "," + stamps_ns[i] + ".png\n";
  }
  writeText(cam / "data.csv", csv);
}

TEST(DatasetTest, ReadsAslLayoutWithNanosecondTimestamps) {
  TempDir tmp("asl");
  const fs::path cam = tmp.path() / "mav0" / "cam0";
  writeAslFrames(tmp.path(), {"1403715273262142976", "1403715273312143104"});
  const DatasetIndex index = openDataset(tmp.path().string());
  EXPECT_EQ(index.layout, DatasetLayout::kAsl);
  ASSERT_EQ(index.frames.size(), 2u);
  // Seconds and nanoseconds are converted separately, so the difference is exact to the
  // double rounding of ~1.4e9 s (ulp 2.4e-7 s).
  EXPECT_NEAR(index.frames[1].timestamp_s - index.frames[0].timestamp_s, 0.050000128, 5e-7);
  EXPECT_EQ(index.frames[0].exposure_ms, 0.0);
  EXPECT_EQ(index.frames[0].index_line, 2);

  writeText(cam / "data.csv", "#timestamp [ns],filename\n1403715273262142976,absent.png\n");
  EXPECT_NE(openError(tmp.path()).find("data.csv:2: image"), std::string::npos);
}

// TUM VI's ASL sequences carry DSO files in dso/: its response and vignette in dso/cam0/,
// and each frame's exposure in dso/cam0/times.txt, which the ASL index does not have.
TEST(DatasetTest, TakesTumViExposuresAndResponseFromItsDsoFolder) {
  TempDir tmp("tumvi");
  const fs::path dso = tmp.path() / "dso" / "cam0";
  writeAslFrames(tmp.path(), {"1520530308199447626", "1520530308249448626"});
  fs::create_directories(dso);
  writeText(dso / "pcalib.txt", "0 1 2\n");
  const std::string both =
      "# timestamp [ns] timestamp [s] exposure [ms]\n"
      "1520530308199447626 1520530308.199447626 1.443\n"
      "1520530308249448626 1520530308.249448626 1.5\n";
  writeText(dso / "times.txt", both);
  DatasetIndex index = openDataset(tmp.path().string());
  ASSERT_EQ(index.frames.size(), 2u);
  EXPECT_EQ(index.frames[0].exposure_ms, 1.443);
  EXPECT_EQ(index.frames[1].exposure_ms, 1.5);
  ASSERT_TRUE(index.pcalib_path.has_value());
  EXPECT_EQ(fs::path(*index.pcalib_path), dso / "pcalib.txt");
  EXPECT_TRUE(index.warnings.empty());

  // A file that misses a frame gives none: the other frame would be read at exposure 1.
  writeText(dso / "times.txt", "1520530308199447626 1520530308.199447626 1.443\n");
  index = openDataset(tmp.path().string());
  EXPECT_EQ(index.frames[0].exposure_ms, 0.0);
  EXPECT_EQ(index.frames[1].exposure_ms, 0.0);
  ASSERT_EQ(index.warnings.size(), 1u);
  EXPECT_NE(index.warnings[0].find("1 of the 2 frames"), std::string::npos) << index.warnings[0];

  // Without the exposure column there is nothing to take, and nothing to warn about.
  writeText(dso / "times.txt", "1520530308199447626 1520530308.199447626\n");
  index = openDataset(tmp.path().string());
  EXPECT_EQ(index.frames[0].exposure_ms, 0.0);
  EXPECT_TRUE(index.warnings.empty());

  writeText(dso / "times.txt", "1520530308199447626 1520530308.2 -1\n");
  EXPECT_NE(openError(tmp.path()).find("times.txt:1: exposure time is negative"),
            std::string::npos)
      << openError(tmp.path());

  // A times.txt that cannot be read is reported, not passed over.
  fs::remove(dso / "times.txt");
  fs::create_symlink("times.txt", dso / "times.txt");  // a loop
  EXPECT_NE(openError(tmp.path()).find("times.txt"), std::string::npos) << openError(tmp.path());
}

TEST(DatasetTest, ReadsEurocStaticClip) {
  const auto dir = test::sharedDataDir("euroc_v101_static_clip");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  const DatasetIndex index = openDataset(dir->string());
  EXPECT_EQ(index.layout, DatasetLayout::kAsl);
  EXPECT_EQ(index.frames.size(), 95u);
  EXPECT_EQ(index.width, 752);
  EXPECT_EQ(index.height, 480);
  ASSERT_FALSE(index.calibration_paths.empty());
  EXPECT_EQ(fs::path(index.calibration_paths[0]).filename(), "sensor.yaml");
  // 95 frames at 20 Hz.
  EXPECT_NEAR(datasetFrameRate(index), 20.0, 0.1);
  EXPECT_NO_THROW(verifyDatasetImages(index));
  const ImageU8 first = readDatasetFrame(index, 0);
  EXPECT_EQ(first.width(), 752);
}

// KITTI odometry: DIR = dataset/sequences/07 with three 16×12 frames in image_0/ (image_1/,
// the right camera, ignored), one timestamp per times.txt line, and calib.txt.
fs::path writeKittiSequence(const fs::path& root) {
  const fs::path sequence = root / "dataset" / "sequences" / "07";
  fs::create_directories(sequence / "image_0");
  fs::create_directories(sequence / "image_1");
  for (int i = 0; i < 3; ++i) {
    const std::string name = "00000" + std::to_string(i) + ".png";
    writeGreyImage(sequence / "image_0" / name, 16, 12, 10 * (i + 1));
    writeGreyImage(sequence / "image_1" / name, 16, 12, 99);
  }
  writeText(sequence / "times.txt", "0.000000e+00\n1.036224e-01\n2.072448e-01\n");
  writeText(sequence / "calib.txt", "P0: 10 0 7.5 0 0 10 5.5 0 0 0 1 0\n");
  return sequence;
}

TEST(DatasetTest, ReadsKittiOdometryLayoutWithItsPoses) {
  TempDir tmp("kitti");
  const fs::path sequence = writeKittiSequence(tmp.path());
  fs::create_directories(tmp.path() / "dataset" / "poses");
  const fs::path poses = tmp.path() / "dataset" / "poses" / "07.txt";
  writeText(poses, "1 0 0 0 0 1 0 0 0 0 1 0\n");
  // With and without a trailing separator, as a shell's completion leaves it.
  for (const std::string& dir : {sequence.string(), sequence.string() + "/"}) {
    const DatasetIndex index = openDataset(dir);
    EXPECT_EQ(index.layout, DatasetLayout::kKitti) << dir;
    EXPECT_STREQ(datasetLayoutName(index.layout), "kitti");
    ASSERT_EQ(index.frames.size(), 3u);
    EXPECT_EQ(index.frames[0].id, "000000");
    EXPECT_EQ(index.frames[2].id, "000002");
    EXPECT_EQ(fs::path(index.frames[2].image_path), sequence / "image_0" / "000002.png");
    EXPECT_DOUBLE_EQ(index.frames[1].timestamp_s, 0.1036224);
    EXPECT_EQ(index.frames[1].exposure_ms, 0.0);  // KITTI records none
    EXPECT_EQ(index.frames[2].index_line, 3);
    EXPECT_EQ(fs::path(index.frames[2].index_file), sequence / "times.txt");
    EXPECT_EQ(index.width, 16);
    EXPECT_EQ(index.height, 12);
    ASSERT_EQ(index.calibration_paths.size(), 1u);
    EXPECT_EQ(fs::path(index.calibration_paths[0]), sequence / "calib.txt");
    EXPECT_FALSE(index.pcalib_path.has_value());
    EXPECT_FALSE(index.vignette_path.has_value());
    EXPECT_EQ(index.groundtruth_kind, GroundTruthKind::kCameraKitti);
    ASSERT_TRUE(index.groundtruth_path.has_value());
    EXPECT_TRUE(fs::equivalent(*index.groundtruth_path, poses)) << *index.groundtruth_path;
    EXPECT_EQ(readDatasetFrame(index, 2)(3, 3), 30);  // image_0, not image_1
  }

  // Sequences 11–21 have no poses: no ground truth, and no error.
  fs::remove(poses);
  const DatasetIndex index = openDataset(sequence.string());
  EXPECT_EQ(index.groundtruth_kind, GroundTruthKind::kNone);
  EXPECT_FALSE(index.groundtruth_path.has_value());
}

// Frame numbers count timestamps, not lines: a blank or comment line shifts the line, not the
// image.
TEST(DatasetTest, KittiFramesAreNumberedByTimestampNotByLine) {
  TempDir tmp("kitti_blank");
  const fs::path sequence = writeKittiSequence(tmp.path());
  writeText(sequence / "times.txt", "# t\n0.0\n\n0.1\n0.2\n\n");
  const DatasetIndex index = openDataset(sequence.string());
  ASSERT_EQ(index.frames.size(), 3u);
  EXPECT_EQ(index.frames[1].id, "000001");
  EXPECT_EQ(index.frames[1].index_line, 4);
  EXPECT_EQ(fs::path(index.frames[1].image_path).filename(), "000001.png");
}

TEST(DatasetTest, KittiTimesLineWithOtherThanOneNumberNamesTheLine) {
  TempDir tmp("kitti_bad_line");
  const fs::path sequence = writeKittiSequence(tmp.path());
  writeText(sequence / "times.txt", "0.0\n0.1 12.5\n0.2\n");
  std::string error = openError(sequence);
  EXPECT_NE(error.find("times.txt:2: expected one timestamp in seconds (KITTI layout), got 2 "
                       "fields"),
            std::string::npos)
      << error;
  writeText(sequence / "times.txt", "0.0\n0.1\n0.2s\n");
  error = openError(sequence);
  EXPECT_NE(error.find("times.txt:3: timestamp '0.2s' is not a number"), std::string::npos)
      << error;
  writeText(sequence / "times.txt", "0.0\n0.1\n0.1\n");
  error = openError(sequence);
  EXPECT_NE(error.find("times.txt:3: timestamp"), std::string::npos) << error;
  EXPECT_NE(error.find("is not after the previous one"), std::string::npos) << error;
}

TEST(DatasetTest, KittiMissingImagesAreNamedOrSkippedAsInTheOtherLayouts) {
  TempDir tmp("kitti_missing");
  const fs::path sequence = writeKittiSequence(tmp.path());
  fs::remove(sequence / "image_0" / "000001.png");
  const std::string error = openError(sequence);
  EXPECT_NE(error.find("times.txt:2: image '"), std::string::npos) << error;
  EXPECT_NE(error.find("000001.png' not found"), std::string::npos) << error;

  DatasetOpenOptions skip;
  skip.skip_missing_images = true;
  const DatasetIndex index = openDataset(sequence.string(), skip);
  ASSERT_EQ(index.frames.size(), 2u);
  EXPECT_EQ(index.frames[1].id, "000002");
  EXPECT_EQ(index.frames[1].index_line, 3);
  ASSERT_EQ(index.warnings.size(), 1u);
  EXPECT_NE(index.warnings[0].find("1 frame(s) dropped"), std::string::npos) << index.warnings[0];
}

// images/ decides for TUM: a TUM directory that also holds an image_0/ and a calib.txt.
TEST(DatasetTest, DirectoryWithImagesAndImage0StaysTum) {
  TempDir tmp("kitti_and_tum");
  writeTumDataset(tmp.path());
  fs::create_directories(tmp.path() / "image_0");
  writeGreyImage(tmp.path() / "image_0" / "000000.png", 16, 12, 0);
  writeText(tmp.path() / "calib.txt", "P0: 10 0 7.5 0 0 10 5.5 0 0 0 1 0\n");
  const DatasetIndex index = openDataset(tmp.path().string());
  EXPECT_EQ(index.layout, DatasetLayout::kTum);
  EXPECT_EQ(index.frames.size(), 3u);
  EXPECT_EQ(index.frames[1].id, "001");

  // Without images/ the same directory is KITTI (and its times.txt, TUM's, is refused).
  fs::remove_all(tmp.path() / "images");
  const std::string error = openError(tmp.path());
  EXPECT_NE(error.find("times.txt:2: expected one timestamp in seconds (KITTI layout)"),
            std::string::npos)
      << error;
}

}  // namespace
}  // namespace omnidso
