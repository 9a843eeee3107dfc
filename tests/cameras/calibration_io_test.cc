// Calibration files (calibration_io.hpp): round trips and rejection of bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>
#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/core/error.hpp>

#include "test_data.hpp"

#include "vector_literal.hpp"

namespace omnidso {
namespace {

using test::vec;

// Parameters with many significant digits, so that a lossy write would show.
std::vector<Camera> everyModel() {
  return {
      Camera::create("pinhole", vec({460.123456789, 458.7, 319.25, 239.5}), 640, 480),
      Camera::create("ucm", vec({380.1, 379.3, 320.2, 239.1, 0.912345678901}), 640, 480),
      Camera::create("eucm", vec({250.5, 251.25, 320.3, 240.2, 0.6123, 1.1}), 640, 480),
      Camera::create("ds", vec({180.1, 181.2, 319.1, 240.7, 0.2, 0.6}), 640, 480),
      Camera::create("kb4", vec({200, 201, 319.4, 239.6, 0.01, -0.005, 0.001, -2e-4}), 640, 480),
      Camera::create("pinhole-radtan",
                     vec({458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
                          1.76187114e-05}),
                     752, 480),
      Camera::create("ucm-radtan",
                     vec({408.911, 410.488, 630.280, 431.917, 1.05343, -0.0082879, 0.0117789,
                          0.0228246, -0.0041849}),
                     1280, 800),
      Camera::create("fov", vec({446.91584, 556.13952, 637.2728, 509.770464, 0.934785123456789}),
                     1280, 1024)};
}

class CalibrationIoTest : public ::testing::Test {
 protected:
  // One directory per process: ctest runs the tests in parallel processes.
  static std::filesystem::path dir() {
    return std::filesystem::path(::testing::TempDir()) /
           ("omnidso_calibration_io_test_" + std::to_string(::getpid()));
  }
  void TearDown() override {
    std::error_code ignored;
    std::filesystem::remove_all(dir(), ignored);
  }
  std::string path(const std::string& name) const {
    std::filesystem::create_directories(dir());
    return (dir() / name).string();
  }
  std::string write(const std::string& name, const std::string& content) const {
    const std::string p = path(name);
    std::ofstream(p) << content;
    return p;
  }
  // The message of the omnidso::Error that loadCalibration(file) throws.
  static std::string loadError(const std::string& file) {
    try {
      loadCalibration(file);
    } catch (const Error& e) {
      return e.what();
    }
    return "(no error)";
  }
};

// Writes are at 17 significant digits, which round-trip every double exactly.
void expectSameCamera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.modelName(), b.modelName());
  EXPECT_EQ(a.width(), b.width());
  EXPECT_EQ(a.height(), b.height());
  EXPECT_EQ(a.params(), b.params()) << a.modelName();
}

TEST_F(CalibrationIoTest, KalibrRoundTripsEveryModel) {
  for (const Camera& camera : everyModel()) {
    const std::string file = path("camchain_" + camera.modelName() + ".yaml");
    saveKalibr(file, camera);
    EXPECT_EQ(detectCalibrationFormat(file), CalibrationFormat::kKalibr);
    expectSameCamera(loadCalibration(file), camera);
  }
}

TEST_F(CalibrationIoTest, DsoCameraTxtRoundTripsItsModels) {
  for (const Camera& camera : everyModel()) {
    const std::string name = camera.modelName();
    const std::string file = path("camera_" + name + ".txt");
    if (name == "eucm" || name == "ds" || name == "ucm-radtan") {
      EXPECT_THROW(saveDsoCameraTxt(file, camera), Error) << name;
      continue;
    }
    saveDsoCameraTxt(file, camera);
    EXPECT_EQ(detectCalibrationFormat(file), CalibrationFormat::kDsoCameraTxt);
    expectSameCamera(loadCalibration(file), camera);
  }
}

TEST_F(CalibrationIoTest, ReadsKalibrConventions) {
  // Kalibr's omni order is [xi, fu, fv, pu, pv]; no cam0 level is needed.
  const Camera omni = loadCalibration(write("omni.yaml",
                                            "camera_model: omni\n"
                                            "intrinsics: [1.1, 500, 501, 320, 240]\n"
                                            "distortion_model: radtan\n"
                                            "distortion_coeffs: [0.1, 0.2, 0.3, 0.4]\n"
                                            "resolution: [640, 480]\n"));
  EXPECT_EQ(omni.modelName(), "ucm-radtan");
  EXPECT_EQ(omni.params(), vec({500, 501, 320, 240, 1.1, 0.1, 0.2, 0.3, 0.4}));
  // pinhole + equidistant is Kannala–Brandt; ds is [xi, alpha, fu, fv, pu, pv].
  const Camera kb = loadCalibration(write("kb.yaml",
                                          "cam0:\n  camera_model: pinhole\n"
                                          "  intrinsics: [190, 191, 254, 256]\n"
                                          "  distortion_model: equidistant\n"
                                          "  distortion_coeffs: [0.01, 0.02, 0.03, 0.04]\n"
                                          "  resolution: [512, 512]\n"
                                          "  rostopic: /cam0/image_raw\n"));
  EXPECT_EQ(kb.modelName(), "kb4");
  EXPECT_EQ(kb.params(), vec({190, 191, 254, 256, 0.01, 0.02, 0.03, 0.04}));
  const Camera ds = loadCalibration(write("ds.yaml",
                                          "cam0:\n  camera_model: ds\n"
                                          "  intrinsics: [-0.2, 0.59, 156, 155, 254, 256]\n"
                                          "  distortion_model: none\n"
                                          "  distortion_coeffs: []\n"
                                          "  resolution: [512, 512]\n"));
  EXPECT_EQ(ds.modelName(), "ds");
  EXPECT_EQ(ds.params(), vec({156, 155, 254, 256, -0.2, 0.59}));
}

TEST_F(CalibrationIoTest, DsoRelativeIntrinsicsAndAliases) {
  // cx, cy < 1: fractions of the image size, pixel-corner origin → fx·w, cx·w − 0.5.
  const Camera relative =
      loadCalibration(write("relative.txt", "Pinhole 0.5 0.6 0.5 0.5 0\n640 480\ncrop\n640 480\n"));
  EXPECT_EQ(relative.params(), vec({320, 288, 319.5, 239.5}));
  const Camera equi = loadCalibration(write(
      "equi.txt", "EquiDistant 190 191 254 256 0.01 0.02 0.03 0.04\n512 512\ncrop\n512 512\n"));
  EXPECT_EQ(equi.modelName(), "kb4");
  // DSO reads 8 numbers without a keyword as RadTan.
  const Camera radtan =
      loadCalibration(write("bare.txt", "458 457 367 248 -0.28 0.07 0.0002 0.00002\n752 480\n"));
  EXPECT_EQ(radtan.modelName(), "pinhole-radtan");
  EXPECT_EQ(radtan.width(), 752);
  const Camera ucm = loadCalibration(write("ucm.txt", "Omni 200 201 240 239 1.1\n480 480\n"));
  EXPECT_EQ(ucm.params(), vec({200, 201, 240, 239, 1.1}));
}

// TUM monoVO's camera.txt: 5 bare numbers in the relative form. DSO reads 5 numbers without a
// keyword as FOV (ATAN): fx·w, fy·h, cx·w − 0.5, cy·h − 0.5 (pixel-centre origin), ω as is:
//   0.349153·1280 = 446.91584, 0.543105·1024 = 556.13952,
//   0.49826·1280 − 0.5 = 637.2728, 0.498311·1024 − 0.5 = 509.770464.
// Products of short decimals: 1e-9 px covers the binary rounding of the inputs.
TEST_F(CalibrationIoTest, DsoFiveBareNumbersAreTheFovModel) {
  const Camera tum = loadCalibration(write(
      "tum_monovo.txt", "0.349153 0.543105 0.49826 0.498311 0.934785\n1280 1024\ncrop\n640 480\n"));
  EXPECT_EQ(tum.modelName(), "fov");
  EXPECT_EQ(tum.width(), 1280);
  EXPECT_EQ(tum.height(), 1024);
  const Eigen::VectorXd expected = vec({446.91584, 556.13952, 637.2728, 509.770464, 0.934785});
  EXPECT_LT((tum.params() - expected).cwiseAbs().maxCoeff(), 1e-9) << tum.params().transpose();
  // The keyword form, absolute intrinsics.
  const Camera keyword =
      loadCalibration(write("fov.txt", "FOV 446.9 556.1 637.3 509.8 0.93\n1280 1024\n"));
  EXPECT_EQ(keyword.modelName(), "fov");
  EXPECT_EQ(keyword.params(), vec({446.9, 556.1, 637.3, 509.8, 0.93}));
  // What saveDsoCameraTxt writes for it: `FOV fx fy cx cy w` (17 significant digits).
  const std::string out = path("fov_written.txt");
  saveDsoCameraTxt(out, keyword);
  std::ifstream written(out);
  std::string keyword_written;
  std::vector<double> numbers(5);
  written >> keyword_written >> numbers[0] >> numbers[1] >> numbers[2] >> numbers[3] >> numbers[4];
  EXPECT_EQ(keyword_written, "FOV");
  EXPECT_EQ(numbers, std::vector<double>({446.9, 556.1, 637.3, 509.8, 0.93}));
  // A bare line must have 5 (FOV) or 8 (RadTan) numbers; ω outside (0, π) is refused.
  EXPECT_NE(loadError(write("six.txt", "1 2 3 4 5 6\n640 480\n"))
                .find(":1: a line without a model keyword takes 5 numbers (FOV"),
            std::string::npos);
  EXPECT_NE(loadError(write("omega.txt", "FOV 400 400 320 240 3.5\n640 480\n"))
                .find(":1: camera model 'fov': w (the field-of-view parameter omega) must be in"),
            std::string::npos);
}

// Kalibr: camera_model pinhole with distortion_model fov and one coefficient [w].
TEST_F(CalibrationIoTest, KalibrPinholeWithFovDistortionIsTheFovModel) {
  const Camera fov = loadCalibration(write("kalibr_fov.yaml",
                                           "cam0:\n  camera_model: pinhole\n"
                                           "  intrinsics: [446.9, 556.1, 637.3, 509.8]\n"
                                           "  distortion_model: fov\n"
                                           "  distortion_coeffs: [0.934785]\n"
                                           "  resolution: [1280, 1024]\n"));
  EXPECT_EQ(fov.modelName(), "fov");
  EXPECT_EQ(fov.params(), vec({446.9, 556.1, 637.3, 509.8, 0.934785}));
  // Written back in the same form (the round trip itself: KalibrRoundTripsEveryModel).
  const std::string out = path("kalibr_fov_written.yaml");
  saveKalibr(out, fov);
  std::ifstream written(out);
  const std::string text((std::istreambuf_iterator<char>(written)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("camera_model: pinhole"), std::string::npos) << text;
  EXPECT_NE(text.find("distortion_model: fov"), std::string::npos) << text;
  EXPECT_NE(text.find("distortion_coeffs: [0.93478499999999998]"), std::string::npos) << text;
}

TEST_F(CalibrationIoTest, KalibrErrorsNameTheFileAndField) {
  struct Case {
    std::string content;
    std::string field;
    std::string reason;
  };
  const std::string tail = "  resolution: [640, 480]\n";
  const std::vector<Case> cases = {
      {"cam0:\n  camera_model: fancy\n  intrinsics: [1, 2, 3, 4]\n" + tail,
       "field 'cam0.camera_model'", "unknown camera model 'fancy'"},
      {"cam0:\n  camera_model: omni\n  intrinsics: [1, 2, 3, 4]\n" + tail,
       "field 'cam0.intrinsics'", "expected 5 values"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [-400, 400, 320, 240]\n" + tail,
       "field 'cam0.intrinsics'", "must be positive"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, .nan, 320, 240]\n" + tail,
       "field 'cam0.intrinsics'", "element 1 is not a finite number"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, abc, 320, 240]\n" + tail,
       "field 'cam0.intrinsics'", "element 1 is not a number"},
      {"cam0:\n  camera_model: omni\n  intrinsics: [-1, 400, 400, 320, 240]\n" + tail,
       "field 'cam0.intrinsics'", "xi must be >= 0"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n"
       "  distortion_model: radtan\n  distortion_coeffs: [0.1, 0.2]\n" +
           tail,
       "field 'cam0.distortion_coeffs'", "expected 4 values"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n"
       "  distortion_model: fov\n  distortion_coeffs: [0.9, 0.1]\n" +
           tail,
       "field 'cam0.distortion_coeffs'", "expected 1 values [w]"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n"
       "  distortion_model: fov\n  distortion_coeffs: [0.0]\n" +
           tail,
       "field 'cam0.distortion_coeffs'", "w must be in (0, pi)"},
      {"cam0:\n  camera_model: omni\n  intrinsics: [0.9, 400, 400, 320, 240]\n"
       "  distortion_model: fov\n  distortion_coeffs: [0.9]\n" +
           tail,
       "field 'cam0.distortion_model'", "pinhole: none, radtan, equidistant, fov"},
      {"cam0:\n  camera_model: eucm\n  intrinsics: [0.5, 1, 400, 400, 320, 240]\n"
       "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n" +
           tail,
       "field 'cam0.distortion_model'", "not supported with camera_model 'eucm'"},
      {"cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n"
       "  resolution: [640]\n",
       "field 'cam0.resolution'", "expected 2 values"},
      {"cam0:\n  intrinsics: [400, 400, 320, 240]\n" + tail, "field 'cam0.camera_model'",
       "missing"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string file = write("bad_" + std::to_string(i) + ".yaml", cases[i].content);
    const std::string message = loadError(file);
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].field), std::string::npos) << message;
    EXPECT_NE(message.find(cases[i].reason), std::string::npos) << message;
  }
}

TEST_F(CalibrationIoTest, MalformedYamlNamesTheFileAndLine) {
  const std::string file =
      write("malformed.yaml", "cam0:\n  camera_model: pinhole\n  intrinsics: [1, 2\n");
  const std::string message = loadError(file);
  EXPECT_NE(message.find(file + ":"), std::string::npos) << message;
  EXPECT_NE(message.find("malformed YAML"), std::string::npos) << message;
}

TEST_F(CalibrationIoTest, DsoErrorsNameTheFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"Fisheye 1 2 3 4 5\n640 480\n", ":1: unknown camera model 'Fisheye'"},
      {"Pinhole 400 400 320\n640 480\n", ":1: camera model 'pinhole' takes 5 numbers, got 3"},
      {"Pinhole -400 400 320 240 0\n640 480\n", ":1: camera model 'pinhole': focal lengths"},
      {"Pinhole 400 nan 320 240 0\n640 480\n", ":1: 'nan' is not finite"},
      {"Pinhole 400 400 320 240 0\n640 x\n", ":2: expected 'in_width in_height'"},
      {"Pinhole 400 400 320 240 0\n640 480\nsquash\n640 480\n", ":3: expected 'crop'"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string file = write("bad_" + std::to_string(i) + ".txt", cases[i].first);
    const std::string message = loadError(file);
    EXPECT_NE(message.find(file + cases[i].second), std::string::npos) << message;
  }
}

TEST_F(CalibrationIoTest, ReadsEurocSensorYaml) {
  const auto dir = test::sharedDataDir("euroc_v101_static_clip");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  const std::string file = (*dir / "mav0" / "cam0" / "sensor.yaml").string();
  EXPECT_EQ(detectCalibrationFormat(file), CalibrationFormat::kEurocSensor);
  const SensorCalibration calib = loadEurocSensor(file);
  EXPECT_EQ(calib.camera.modelName(), "pinhole-radtan");
  EXPECT_EQ(calib.camera.width(), 752);
  EXPECT_EQ(calib.camera.height(), 480);
  EXPECT_EQ(calib.camera.params(), vec({458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907,
                                        0.00019359, 1.76187114e-05}));
  // The published T_BS (row-major): translation as stored; rotation orthonormal to ~1e-9.
  EXPECT_EQ(calib.T_body_sensor.translation(),
            Eigen::Vector3d(-0.0216401454975, -0.064676986768, 0.00981073058949));
  EXPECT_NEAR(calib.T_body_sensor.rotationMatrix()(0, 1), -0.999880929698, 1e-8);
  EXPECT_EQ(loadCalibration(file).modelName(), "pinhole-radtan");
}

// Kalibr's camera–IMU extrinsics (TUM VI's dso/camchain.yaml carries them beside cam0's model).
TEST_F(CalibrationIoTest, ReadsKalibrCameraImuExtrinsics) {
  const std::string model =
      "  camera_model: pinhole\n  intrinsics: [190.0, 190.0, 255.5, 255.5]\n"
      "  distortion_model: equidistant\n  distortion_coeffs: [0.003, 0.0007, -0.002, 0.0002]\n"
      "  resolution: [512, 512]\n";
  // A quarter turn about z and an offset, as rows.
  const std::string file = write(
      "camchain_imu.yaml", "cam0:\n" + model +
                               "  T_cam_imu:\n  - [0.0, -1.0, 0.0, 0.04]\n"
                               "  - [1.0, 0.0, 0.0, -0.07]\n  - [0.0, 0.0, 1.0, -0.045]\n"
                               "  - [0.0, 0.0, 0.0, 1.0]\n");
  const std::optional<SE3d> cam_imu = loadKalibrCamImu(file);
  ASSERT_TRUE(cam_imu.has_value());
  EXPECT_EQ(cam_imu->translation(), Eigen::Vector3d(0.04, -0.07, -0.045));
  Eigen::Matrix3d quarter_turn;
  quarter_turn << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_LT((cam_imu->rotationMatrix() - quarter_turn).norm(), 1e-15);
  EXPECT_EQ(loadCalibration(file).modelName(), "kb4");  // the model reads as before

  // No extrinsics: nothing, and no error.
  EXPECT_FALSE(loadKalibrCamImu(write("camchain_plain.yaml", "cam0:\n" + model)).has_value());

  auto error = [&](const std::string& rows) {
    try {
      loadKalibrCamImu(write("camchain_bad.yaml", "cam0:\n" + model + "  T_cam_imu:\n" + rows));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string last = "  - [0.0, 0.0, 0.0, 1.0]\n";
  // A scaled rotation is not rigid.
  EXPECT_NE(error("  - [2.0, 0.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n"
                  "  - [0.0, 0.0, 1.0, 0.0]\n" + last)
                .find("field 'cam0.T_cam_imu': not a rigid transformation"),
            std::string::npos);
  EXPECT_NE(error("  - [1.0, 0.0, 0.0]\n  - [0.0, 1.0, 0.0, 0.0]\n  - [0.0, 0.0, 1.0, 0.0]\n" +
                  last)
                .find("field 'cam0.T_cam_imu': expected 4 values in row 0"),
            std::string::npos);
  EXPECT_NE(error("  - [1.0, 0.0, 0.0, 0.0]\n" + last).find("four rows of four numbers"),
            std::string::npos);
}

// KITTI odometry sequence 07's calib.txt (P0..P3 and Tr; P1's −P0[0]·baseline in P1[3]).
const char* const kKitti07P0 =
    "P0: 7.070912000000e+02 0.000000000000e+00 6.018873000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 7.070912000000e+02 1.831104000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n";
const char* const kKitti07Rest =
    "P1: 7.070912000000e+02 0.000000000000e+00 6.018873000000e+02 -3.798145000000e+02 "
    "0.000000000000e+00 7.070912000000e+02 1.831104000000e+02 0.000000000000e+00 "
    "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00\n"
    "Tr: -1.857739385241e-03 -9.999659513510e-01 -8.039975204516e-03 -4.784029760483e-03 "
    "-6.481465826011e-03 8.051860151134e-03 -9.999466081774e-01 -7.337429464231e-02 "
    "9.999773098287e-01 -1.805528627661e-03 -6.496203536139e-03 -3.339968064433e-01\n";

TEST_F(CalibrationIoTest, ReadsKittiCalibP0AtTheGivenImageSize) {
  const std::string file = write("calib.txt", std::string(kKitti07P0) + kKitti07Rest);
  EXPECT_EQ(detectCalibrationFormat(file), CalibrationFormat::kKittiCalib);
  const Camera camera = loadKittiCalib(file, 1226, 370);
  EXPECT_EQ(camera.modelName(), "pinhole");
  EXPECT_EQ(camera.width(), 1226);
  EXPECT_EQ(camera.height(), 370);
  // KITTI's principal point is already pixel-centred (OpenCV's convention): no 0.5 shift.
  EXPECT_EQ(camera.params(), vec({707.0912, 707.0912, 601.8873, 183.1104}));
  // P0 after the other lines is found too.
  const std::string reordered =
      write("calib_reordered.txt", std::string(kKitti07Rest) + kKitti07P0);
  EXPECT_EQ(detectCalibrationFormat(reordered), CalibrationFormat::kKittiCalib);
  EXPECT_EQ(loadKittiCalib(reordered, 1241, 376).params()[2], 601.8873);
  // DSO's camera.txt, also .txt, is still told apart.
  const std::string dso = write("camera.txt", "Pinhole 400 400 320 240 0\n640 480\n");
  EXPECT_EQ(detectCalibrationFormat(dso), CalibrationFormat::kDsoCameraTxt);
}

TEST_F(CalibrationIoTest, LoadCalibrationSendsKittiCalibToItsDataset) {
  const std::string file = write("calib.txt", std::string(kKitti07P0) + kKitti07Rest);
  const std::string message = loadError(file);
  EXPECT_NE(message.find(file + ": KITTI's calib.txt has no image size"), std::string::npos)
      << message;
  EXPECT_NE(message.find("datasetCamera"), std::string::npos) << message;
}

TEST_F(CalibrationIoTest, KittiCalibErrorsNameTheFileAndLine) {
  auto error = [&](const std::string& name, const std::string& content) {
    const std::string file = write(name, content);
    try {
      loadKittiCalib(file, 1241, 376);
    } catch (const Error& e) {
      return std::string(e.what()).substr(file.size());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error("short.txt", std::string(kKitti07Rest) + "P0: 707 0 601 0 0 707 183 0 0 0 1\n"),
            ":3: P0 takes 12 numbers (a 3x4 projection matrix, row-major), got 11");
  EXPECT_EQ(error("word.txt", "P0: 707 0 601 0 0 707 18x3 0 0 0 1 0\n"),
            ":1: P0: '18x3' is not a number");
  EXPECT_EQ(error("nan.txt", "P0: 707 0 601 0 0 nan 183 0 0 0 1 0\n"),
            ":1: P0: 'nan' is not finite");
  EXPECT_EQ(error("fx.txt", "P0: -707 0 601 0 0 707 183 0 0 0 1 0\n"),
            ":1: P0: focal lengths must be positive, got fx -707 and fy 707");
  EXPECT_EQ(error("fy.txt", "P0: 707 0 601 0 0 0 183 0 0 0 1 0\n"),
            ":1: P0: focal lengths must be positive, got fx 707 and fy 0");
  EXPECT_EQ(error("skew.txt", "P0: 707 0.5 601 0 0 707 183 0 0 0 1 0\n").find(
                ":1: P0 is not a rectified pinhole"),
            0u);
  EXPECT_EQ(error("no_p0.txt", kKitti07Rest),
            ": no 'P0:' line (KITTI's calib.txt holds image_0's projection there)");
  // An image size Camera refuses is reported at P0's line too.
  const std::string file = write("size.txt", kKitti07P0);
  try {
    loadKittiCalib(file, 0, 376);
    ADD_FAILURE() << "a 0-pixel-wide image was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find(file + ":1: "), 0u) << e.what();
  }
}

}  // namespace
}  // namespace omnidso
