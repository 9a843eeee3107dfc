// Synthetic sequences written as TUM-layout datasets and read back with core's reader.
#include <omnidso/synth/dataset_writer.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <omnidso/cameras/calibration_io.hpp>
#include <omnidso/cameras/field_of_view.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/photometric_calibration.hpp>
#include <omnidso/core/trajectory_io.hpp>
#include <omnidso/synth/dataset_loading.hpp>

#include "synth_test_util.hpp"

namespace omnidso::synth {
namespace {
namespace fs = std::filesystem;
using test::smallSequenceConfig;
using test::TempDir;

TEST(SyntheticDatasetTest, WriteThenReadGivesTheSameFramesTimesCalibrationAndGroundTruth) {
  TempDir tmp("roundtrip");
  const SyntheticSequenceConfig config = smallSequenceConfig(4);
  SyntheticSequence written(config);
  writeSyntheticDataset(written, tmp.str());

  // The same configuration rendered again in memory: the reference frames.
  SyntheticSequence reference(config);
  const DatasetIndex index = openDataset(tmp.str());
  EXPECT_EQ(index.layout, DatasetLayout::kTum);
  ASSERT_EQ(index.frames.size(), 4u);
  EXPECT_EQ(index.width, 96);
  EXPECT_EQ(index.height, 96);
  EXPECT_NO_THROW(verifyDatasetImages(index));
  for (size_t k = 0; k < index.frames.size(); ++k) {
    const SyntheticSequence::Frame frame = reference.renderNext();
    EXPECT_EQ(index.frames[k].id, frameId(static_cast<int>(k), 4));
    // Exact: times.txt holds round-trip decimals of the values used.
    EXPECT_EQ(index.frames[k].timestamp_s, frame.timestamp_s);
    EXPECT_EQ(index.frames[k].exposure_ms, frame.exposure_ms);
    EXPECT_TRUE(readDatasetFrame(index, k) == frame.image) << "frame " << k;
  }

  // Calibration: camchain.yaml (and camera.txt, UCM being in this project's DSO format).
  ASSERT_FALSE(index.calibration_paths.empty());
  const Camera camera = loadCalibration(index.calibration_paths.front());
  EXPECT_EQ(camera.modelName(), "ucm");
  EXPECT_EQ(camera.width(), 96);
  // Written with round-trip precision by the Kalibr writer; 1e-9 px allows a last digit.
  EXPECT_LT((camera.params() - written.camera().params()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT(maximumFovDeg(camera), 180.0);

  // Photometric calibration: G⁻¹ as rendered; V up to 16-bit quantisation (½ / 65535 of the
  // maximum, and the maximum itself is ≤ 1).
  const PhotometricCalibration photometric =
      PhotometricCalibration::fromFiles(*index.pcalib_path, *index.vignette_path);
  const InverseResponse expected_response =
      written.renderer().photometric().inverseResponseTable();
  for (int k = 0; k < kResponseSize; ++k) {
    EXPECT_NEAR(photometric.inverseResponseTable()[k], expected_response[k], 1e-6);
  }
  const ImageF& vignette = written.renderer().vignette();
  const float vignette_max = *std::max_element(vignette.data(), vignette.data() + vignette.size());
  for (int v = 0; v < 96; v += 7) {
    for (int u = 0; u < 96; u += 7) {
      EXPECT_NEAR(photometric.vignette()(u, v), vignette(u, v) / vignette_max, 1.0 / 65535);
    }
  }

  // Ground truth: bit-identical poses at the frame timestamps.
  ASSERT_EQ(index.groundtruth_kind, GroundTruthKind::kCameraTum);
  const Trajectory gt = cameraGroundTruth(index);
  ASSERT_EQ(gt.size(), 4u);
  for (size_t k = 0; k < gt.size(); ++k) {
    EXPECT_EQ(gt[k].timestamp, index.frames[k].timestamp_s);
    EXPECT_LT((gt[k].pose.matrix() - written.groundTruth()[k].pose.matrix()).norm(), 1e-12);
  }
}

// The poses in groundtruth.txt are those the renderer used: rendering with them reproduces
// the images byte for byte. A scene point seen in frames 0 and 2 projects through them to
// pixels of the same scene radiance, after undoing G, V and t (photometric correction).
TEST(SyntheticDatasetTest, GroundTruthPosesAreThoseRendered) {
  TempDir tmp("poses");
  SyntheticSequenceConfig config = smallSequenceConfig(3);
  config.photometric.noise = false;
  SyntheticSequence sequence(config);
  writeSyntheticDataset(sequence, tmp.str());
  const DatasetIndex index = openDataset(tmp.str());
  const Trajectory gt = cameraGroundTruth(index);
  for (size_t k = 0; k < 3; ++k) {
    const ImageU8 rerendered =
        sequence.renderer().render({gt[k].pose}, index.frames[k].exposure_ms, k);
    EXPECT_TRUE(rerendered == readDatasetFrame(index, k)) << "frame " << k;
  }

  const Camera& camera = sequence.camera();
  const PhotometricModel& model = sequence.renderer().photometric();
  const ImageU8 first = readDatasetFrame(index, 0);
  const ImageU8 third = readDatasetFrame(index, 2);
  // Scene radiance from a pixel value: B = G⁻¹(I) / (gain · t · V).
  auto radianceOf = [&](const ImageU8& image, int u, int v, double exposure_ms) {
    return model.inverseResponse(image(u, v)) /
           (model.gain_per_ms * exposure_ms * sequence.renderer().vignette()(u, v));
  };
  int compared = 0;
  constexpr int kMaxSpread = 3;  // grey levels over the 5×5 neighbourhood
  for (int v = 8; v < 88; v += 2) {
    for (int u = 8; u < 88; u += 2) {
      Eigen::Vector3d bearing;
      ASSERT_TRUE(camera.unproject(Eigen::Vector2d(u, v), bearing));
      RayHit hit;
      const Eigen::Vector3d ray = gt[0].pose.rotation() * bearing;
      ASSERT_TRUE(sequence.scene().intersect(gt[0].pose.translation().cast<float>(),
                                             ray.cast<float>(), &hit));
      const Eigen::Vector3d point = gt[0].pose.translation() + hit.distance * ray;
      Eigen::Vector2d uv;
      if (!camera.project(gt[2].pose.inverse() * point, uv)) continue;
      const int u2 = static_cast<int>(std::lround(uv.x()));
      const int v2 = static_cast<int>(std::lround(uv.y()));
      if (u2 < 2 || v2 < 2 || u2 > 93 || v2 > 93) continue;
      // Visible in frame 2: its ray hits the point, not an occluder.
      RayHit hit2;
      const Eigen::Vector3d to_point = point - gt[2].pose.translation();
      sequence.scene().intersect(gt[2].pose.translation().cast<float>(),
                                 to_point.normalized().cast<float>(), &hit2);
      if (std::abs(hit2.distance - to_point.norm()) > 1e-3) continue;
      // Only where the radiance is smooth over ±1.5 px in both frames (anti-aliasing
      // error small), judged by the pixel values around both positions.
      auto spread = [](const ImageU8& image, int cu, int cv) {
        int lo = 255, hi = 0;
        for (int dv = -2; dv <= 2; ++dv) {
          for (int du = -2; du <= 2; ++du) {
            lo = std::min<int>(lo, image(cu + du, cv + dv));
            hi = std::max<int>(hi, image(cu + du, cv + dv));
          }
        }
        return hi - lo;
      };
      if (spread(first, u, v) > kMaxSpread || spread(third, u2, v2) > kMaxSpread) continue;
      const double b0 = radianceOf(first, u, v, index.frames[0].exposure_ms);
      const double b2 = radianceOf(third, u2, v2, index.frames[2].exposure_ms);
      // Each value is within kMaxSpread grey levels of the point's (smoothness) plus ½ of
      // rounding; through G⁻¹ (slope 1.6·(k/255)^0.6 ≤ 1.6) and 1/(gain·t·V) that bounds the
      // radiance error of each frame.
      const double levels = (kMaxSpread + 0.5) * 1.6;
      const double tolerance = levels / (model.gain_per_ms * index.frames[0].exposure_ms *
                                         sequence.renderer().vignette()(u, v)) +
                               levels / (model.gain_per_ms * index.frames[2].exposure_ms *
                                         sequence.renderer().vignette()(u2, v2));
      EXPECT_NEAR(b0, b2, tolerance) << "pixel (" << u << ", " << v << ") → " << uv.transpose();
      EXPECT_NEAR(b0, sequence.scene().radiance(hit), tolerance);
      ++compared;
    }
  }
  EXPECT_GE(compared, 20);
}

TEST(SyntheticDatasetTest, SameSeedSameBytesOtherSeedOtherImages) {
  SyntheticSequence a(smallSequenceConfig(1, 5));
  SyntheticSequence b(smallSequenceConfig(1, 5));
  SyntheticSequence c(smallSequenceConfig(1, 6));
  const ImageU8 image_a = a.renderNext().image;
  EXPECT_TRUE(image_a == b.renderNext().image);
  EXPECT_FALSE(image_a == c.renderNext().image);
}

TEST(SyntheticDatasetTest, RefusesANonEmptyDirectoryUnlessOverwriting) {
  TempDir tmp("refuse");
  std::ofstream(tmp.path() / "keep.txt") << "user data\n";
  SyntheticSequence sequence(smallSequenceConfig(1));
  try {
    writeSyntheticDataset(sequence, tmp.str());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not empty"), std::string::npos) << e.what();
  }
  DatasetWriteOptions options;
  options.overwrite = true;
  writeSyntheticDataset(sequence, tmp.str(), options);
  EXPECT_TRUE(fs::exists(tmp.path() / "times.txt"));
  EXPECT_TRUE(fs::exists(tmp.path() / "keep.txt"));  // only dataset files are replaced
}

TEST(SyntheticDatasetTest, FrameIdsArePaddedToFiveDigitsOrMore) {
  EXPECT_EQ(frameId(42, 500), "00042");
  EXPECT_EQ(frameId(7, 100000), "00007");
  EXPECT_EQ(frameId(123456, 200000), "123456");
}

TEST(SyntheticDatasetTest, CamerasSpanTheRequestedFieldOfView) {
  // The horizontal FoV is measured through the border midpoints, at radius min(w, h)/2
  // from the centre: the radius syntheticCamera puts at fov/2. Bisection and float
  // rounding keep the result within 1e-3°.
  for (const char* model : {"ucm", "eucm", "ds", "kb4", "fov"}) {
    const Camera camera = syntheticCamera(model, 185.0, 120, 120);
    EXPECT_NEAR(horizontalFovDeg(camera), 185.0, 1e-3) << model;
    EXPECT_GT(maximumFovDeg(camera), 180.0) << model;
  }
  const Camera pinhole = syntheticCamera("pinhole", 90.0, 120, 100);
  EXPECT_NEAR(horizontalFovDeg(pinhole), 90.0, 1e-6);
  EXPECT_THROW(syntheticCamera("pinhole", 185.0, 120, 120), Error);
}

TEST(SyntheticDatasetTest, PresetsAreKnownByName) {
  EXPECT_EQ(presetConfig("room185").camera_model, "ucm");
  EXPECT_EQ(presetConfig("room185").width, 480);
  EXPECT_GE(presetConfig("room185_long").frames, 3000);
  EXPECT_EQ(presetConfig("room_pinhole90").camera_model, "pinhole");
  EXPECT_THROW(presetConfig("nonsense"), Error);
}

// The pinhole ablation renders the same scene along the same path.
TEST(SyntheticDatasetTest, PinholeAblationSharesSceneAndTrajectory) {
  SyntheticSequenceConfig config = smallSequenceConfig(3);
  SyntheticSequenceConfig pinhole = config;
  pinhole.camera_model = "pinhole";
  pinhole.fov_deg = 90.0;
  const SyntheticSequence a(config);
  const SyntheticSequence b(pinhole);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(a.groundTruth()[k].pose.matrix() == b.groundTruth()[k].pose.matrix());
  }
  EXPECT_TRUE(a.scene().textures()[3].paddedRadiance() == b.scene().textures()[3].paddedRadiance());
}

}  // namespace
}  // namespace omnidso::synth
