// Camera and camera-frame ground truth of datasets (synth/dataset_loading.hpp): ASL, TUM VI
// and KITTI odometry.
#include <omnidso/synth/dataset_loading.hpp>

#include <gtest/gtest.h>

#include <fstream>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/core/error.hpp>

#include "synth_test_util.hpp"

namespace omnidso::synth {
namespace {
namespace fs = std::filesystem;

// An ASL dataset of two 32×24 frames with a sensor.yaml whose T_BS is a 90° turn about z
// plus an offset, and body ground truth of two poses.
void writeAslDataset(const fs::path& root, int calibration_width) {
  const fs::path cam = root / "mav0" / "cam0";
  fs::create_directories(cam / "data");
  for (const char* stamp : {"1000000000", "1050000000"}) {
    cv::imwrite((cam / "data" / (std::string(stamp) + ".png")).string(),
                cv::Mat(24, 32, CV_8UC1, cv::Scalar(9)));
  }
  std::ofstream(cam / "data.csv") << "#timestamp [ns],filename\n"
                                     "1000000000,1000000000.png\n"
                                     "1050000000,1050000000.png\n";
  std::ofstream(cam / "sensor.yaml")
      << "%YAML:1.0\nsensor_type: camera\n"
         "T_BS:\n  cols: 4\n  rows: 4\n"
         "  data: [0.0, -1.0, 0.0, 0.1,  1.0, 0.0, 0.0, 0.2,  0.0, 0.0, 1.0, 0.3,  0, 0, 0, 1]\n"
         "rate_hz: 20\nresolution: ["
      << calibration_width
      << ", 24]\ncamera_model: pinhole\nintrinsics: [20.0, 20.0, 15.5, 11.5]\n"
         "distortion_model: radial-tangential\ndistortion_coefficients: [0.0, 0.0, 0.0, 0.0]\n";
  fs::create_directories(root / "mav0" / "state_groundtruth_estimate0");
  std::ofstream(root / "mav0" / "state_groundtruth_estimate0" / "data.csv")
      << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
         "q_RS_y [], q_RS_z []\n"
         "1000000000,1.0,2.0,3.0,1.0,0.0,0.0,0.0\n"
         "1050000000,1.5,2.0,3.0,0.70710678118654752,0.70710678118654752,0.0,0.0\n";
}

TEST(DatasetLoadingTest, AslBodyGroundTruthBecomesCameraPosesThroughTbs) {
  test::TempDir tmp("asl_gt");
  writeAslDataset(tmp.path(), 32);
  const DatasetIndex index = openDataset(tmp.str());
  ASSERT_EQ(index.groundtruth_kind, GroundTruthKind::kBodyAsl);
  const Trajectory cameras = cameraGroundTruth(index);
  ASSERT_EQ(cameras.size(), 2u);
  Eigen::Matrix3d r_bs;
  r_bs << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const SE3d t_bs(r_bs, Eigen::Vector3d(0.1, 0.2, 0.3));
  const SE3d body1(Eigen::Quaterniond(std::sqrt(0.5), std::sqrt(0.5), 0, 0),
                   Eigen::Vector3d(1.5, 2.0, 3.0));
  // T_world_cam = T_world_body · T_BS; the file holds 17-digit numbers, so 1e-12.
  EXPECT_LT((cameras[1].pose.matrix() - (body1 * t_bs).matrix()).norm(), 1e-12);
  EXPECT_LT((cameras[0].pose.translation() - Eigen::Vector3d(1.1, 2.2, 3.3)).norm(), 1e-12);
  EXPECT_NEAR(cameras[1].timestamp - cameras[0].timestamp, 0.05, 1e-9);

  const Camera camera = datasetCamera(index);
  EXPECT_EQ(camera.modelName(), "pinhole-radtan");
  EXPECT_EQ(camera.width(), 32);
}

TEST(DatasetLoadingTest, CalibrationForAnotherImageSizeIsRejected) {
  test::TempDir tmp("asl_size");
  writeAslDataset(tmp.path(), 64);
  const DatasetIndex index = openDataset(tmp.str());
  try {
    datasetCamera(index);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sensor.yaml: calibration is for 64x24 images"),
              std::string::npos)
        << e.what();
  }
}

TEST(DatasetLoadingTest, DatasetWithoutGroundTruthSaysSo) {
  test::TempDir tmp("asl_no_gt");
  writeAslDataset(tmp.path(), 32);
  fs::remove_all(tmp.path() / "mav0" / "state_groundtruth_estimate0");
  const DatasetIndex index = openDataset(tmp.str());
  EXPECT_EQ(index.groundtruth_kind, GroundTruthKind::kNone);
  EXPECT_THROW(cameraGroundTruth(index), Error);
}

// TUM VI's files as its DSO users point at them: DIR = dso/cam0 (TUM layout) with the IMU's
// ground truth in dso/gt_imu.csv and the camera–IMU extrinsics in dso/camchain.yaml; and the
// same sequence from its root (ASL layout) without a sensor.yaml.
TEST(DatasetLoadingTest, TumViGroundTruthTakesTheExtrinsicsFromItsCamchain) {
  test::TempDir tmp("tumvi_gt");
  const fs::path dso = tmp.path() / "dso";
  const fs::path cam = dso / "cam0";
  fs::create_directories(cam / "images");
  for (const char* stamp : {"1000000000", "1050000000"}) {
    cv::imwrite((cam / "images" / (std::string(stamp) + ".png")).string(),
                cv::Mat(24, 32, CV_8UC1, cv::Scalar(9)));
  }
  std::ofstream(cam / "times.txt") << "1000000000 1.0 2.0\n1050000000 1.05 2.0\n";
  std::ofstream(cam / "camera.txt") << "Pinhole 20 20 15.5 11.5 0\n32 24\nnone\n32 24\n";
  // x_cam = T_cam_imu x_imu: a quarter turn about z and an offset.
  std::ofstream(dso / "camchain.yaml")
      << "cam0:\n  camera_model: pinhole\n  intrinsics: [20.0, 20.0, 15.5, 11.5]\n"
         "  distortion_model: none\n  distortion_coeffs: []\n  resolution: [32, 24]\n"
         "  T_cam_imu:\n  - [0.0, -1.0, 0.0, 0.1]\n  - [1.0, 0.0, 0.0, 0.2]\n"
         "  - [0.0, 0.0, 1.0, 0.3]\n  - [0.0, 0.0, 0.0, 1.0]\n";
  std::ofstream(dso / "gt_imu.csv")
      << "# timestamp[ns],tx,ty,tz,qw,qx,qy,qz\n"
         "1000000000,1.0,2.0,3.0,1.0,0.0,0.0,0.0\n"
         "1050000000,1.5,2.0,3.0,0.70710678118654752,0.70710678118654752,0.0,0.0\n";
  Eigen::Matrix3d r_ci;
  r_ci << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  const SE3d imu_to_cam = SE3d(r_ci, Eigen::Vector3d(0.1, 0.2, 0.3)).inverse();  // T_imu_cam
  const SE3d imu1(Eigen::Quaterniond(std::sqrt(0.5), std::sqrt(0.5), 0, 0),
                  Eigen::Vector3d(1.5, 2.0, 3.0));

  for (const std::string& dir : {cam.string(), cam.string() + "/"}) {
    const DatasetIndex index = openDataset(dir);
    ASSERT_EQ(index.groundtruth_kind, GroundTruthKind::kBodyAsl) << dir;
    EXPECT_EQ(fs::path(*index.groundtruth_path), dso / "gt_imu.csv");
    EXPECT_EQ(datasetCamera(index).modelName(), "pinhole");  // camera.txt stays first
    const Trajectory cameras = cameraGroundTruth(index);
    ASSERT_EQ(cameras.size(), 2u);
    // T_world_cam = T_world_imu · T_cam_imu⁻¹ (17-digit numbers in the file: 1e-12).
    EXPECT_LT((cameras[1].pose.matrix() - (imu1 * imu_to_cam).matrix()).norm(), 1e-12);
  }

  // From the root: frames from mav0/cam0, the same ground truth through the same extrinsics.
  writeAslDataset(tmp.path(), 32);
  fs::remove_all(tmp.path() / "mav0" / "state_groundtruth_estimate0");
  fs::remove(tmp.path() / "mav0" / "cam0" / "sensor.yaml");
  DatasetIndex index = openDataset(tmp.str());
  ASSERT_EQ(index.groundtruth_kind, GroundTruthKind::kBodyAsl);
  EXPECT_EQ(fs::path(bodyToCamera(index).source), dso / "camchain.yaml");
  EXPECT_LT((cameraGroundTruth(index)[1].pose.matrix() - (imu1 * imu_to_cam).matrix()).norm(),
            1e-12);

  // Without extrinsics anywhere the body's poses are not the camera's: an error, not a guess.
  std::ofstream(dso / "camchain.yaml")
      << "cam0:\n  camera_model: pinhole\n  intrinsics: [20.0, 20.0, 15.5, 11.5]\n"
         "  resolution: [32, 24]\n";
  index = openDataset(tmp.str());
  try {
    cameraGroundTruth(index);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gt_imu.csv: body-frame ground truth needs the camera's "
                                         "extrinsics"),
              std::string::npos)
        << e.what();
  }
}

// A KITTI odometry sequence dataset/sequences/03 of four 32×24 frames, at 0.1 s steps from
// 0.5 s, and dataset/poses/03.txt whose pose k is a translation of k along x (plus a quarter
// turn about z for pose 2, so that a rotation mix-up shows); `poses` lines of them.
fs::path writeKittiSequence(const fs::path& root, int poses) {
  const fs::path sequence = root / "dataset" / "sequences" / "03";
  fs::create_directories(sequence / "image_0");
  std::string times;
  for (int i = 0; i < 4; ++i) {
    cv::imwrite((sequence / "image_0" / ("00000" + std::to_string(i) + ".png")).string(),
                cv::Mat(24, 32, CV_8UC1, cv::Scalar(9)));
    times += std::to_string(0.5 + 0.1 * i) + "\n";
  }
  std::ofstream(sequence / "times.txt") << times;
  std::ofstream(sequence / "calib.txt") << "P0: 20 0 15.5 0 0 21 11.5 0 0 0 1 0\n"
                                           "Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  fs::create_directories(root / "dataset" / "poses");
  std::ofstream pose_file(root / "dataset" / "poses" / "03.txt");
  for (int k = 0; k < poses; ++k) {
    pose_file << (k == 2 ? "0 -1 0 " : "1 0 0 ") << k << (k == 2 ? " 1 0 0 " : " 0 1 0 ")
              << "0 0 0 1 0\n";
  }
  return sequence;
}

TEST(DatasetLoadingTest, KittiCameraIsP0AtTheImagesSize) {
  test::TempDir tmp("kitti_camera");
  const fs::path sequence = writeKittiSequence(tmp.path(), 4);
  const DatasetIndex index = openDataset(sequence.string());
  const Camera camera = datasetCamera(index);
  EXPECT_EQ(camera.modelName(), "pinhole");
  EXPECT_EQ(camera.width(), 32);
  EXPECT_EQ(camera.height(), 24);
  EXPECT_EQ(camera.params(), Eigen::Vector4d(20, 21, 15.5, 11.5));
  // The same file given with --calib (a copy elsewhere) reads the same way.
  fs::copy_file(sequence / "calib.txt", tmp.path() / "kitti_calib.txt");
  EXPECT_EQ(datasetCamera(index, (tmp.path() / "kitti_calib.txt").string()).params(),
            camera.params());
}

TEST(DatasetLoadingTest, KittiPosesGoToTheFramesByPositionWithTheirTimestamps) {
  test::TempDir tmp("kitti_gt");
  // Six poses for four frames: a clip of a longer sequence, fine.
  const fs::path sequence = writeKittiSequence(tmp.path(), 6);
  const DatasetIndex index = openDataset(sequence.string());
  ASSERT_EQ(index.groundtruth_kind, GroundTruthKind::kCameraKitti);
  const Trajectory poses = cameraGroundTruth(index);
  ASSERT_EQ(poses.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(poses[i].timestamp, 0.5 + 0.1 * i) << i;
    EXPECT_EQ(poses[i].pose.translation(), Eigen::Vector3d(i, 0, 0)) << i;
  }
  Eigen::Matrix3d quarter_turn;
  quarter_turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((poses[2].pose.rotationMatrix() - quarter_turn).norm(), 1e-12);
  EXPECT_LT((poses[1].pose.rotationMatrix() - Eigen::Matrix3d::Identity()).norm(), 1e-12);

  // A comment line shifts times.txt's lines but not the frames, nor their poses.
  std::ofstream(sequence / "times.txt") << "# KITTI 03\n0.5\n0.6\n0.7\n0.8\n";
  const Trajectory commented = cameraGroundTruth(openDataset(sequence.string()));
  ASSERT_EQ(commented.size(), 4u);
  EXPECT_EQ(commented[3].pose.translation(), Eigen::Vector3d(3, 0, 0));

  // Frame 1's image missing, skipped: frames 2 and 3 keep poses 2 and 3, not 1 and 2.
  fs::remove(sequence / "image_0" / "000001.png");
  DatasetOpenOptions skip;
  skip.skip_missing_images = true;
  const Trajectory skipped = cameraGroundTruth(openDataset(sequence.string(), skip));
  ASSERT_EQ(skipped.size(), 3u);
  EXPECT_DOUBLE_EQ(skipped[1].timestamp, 0.7);
  EXPECT_EQ(skipped[1].pose.translation(), Eigen::Vector3d(2, 0, 0));
  EXPECT_LT((skipped[1].pose.rotationMatrix() - quarter_turn).norm(), 1e-12);
  EXPECT_EQ(skipped[2].pose.translation(), Eigen::Vector3d(3, 0, 0));
}

TEST(DatasetLoadingTest, KittiPosesEndingBeforeTheFramesAreAnError) {
  test::TempDir tmp("kitti_short_gt");
  const fs::path sequence = writeKittiSequence(tmp.path(), 3);
  const DatasetIndex index = openDataset(sequence.string());
  try {
    cameraGroundTruth(index);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("03.txt: 3 poses, but the frames need 4: the first without one is "
                           "frame 000003 ("),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("times.txt:4)"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace omnidso::synth
