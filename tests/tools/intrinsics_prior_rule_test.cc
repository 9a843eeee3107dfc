// The calibration prior chosen by the view (cli::applyIntrinsicsPrior): a view of a hemisphere
// or more — over the image content, within `native-fov:FOV` — optimises the intrinsics without
// DSO's prior; narrower views, crops and fixed intrinsics keep the options as they were.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <omnidso/cli/dataset_runner.hpp>
#include <omnidso/core/dataset.hpp>
#include <omnidso/core/image_io.hpp>
#include <omnidso/synth/dataset_loading.hpp>
#include <omnidso/synth/dataset_writer.hpp>

#include "synth_test_util.hpp"

namespace omnidso::cli {
namespace {
namespace fs = std::filesystem;

constexpr double kDsoPrior = WindowOptions{}.intrinsics_prior_weight;

// A calibration file without frames: no content to detect, the model's valid pixels count.
DatasetRunOptions runWithCalibration(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  DatasetRunOptions run;
  run.calib = file.string();
  return run;
}

TEST(IntrinsicsPriorRule, AHemisphereFreesTheIntrinsicsNarrowerViewsKeepDsosPrior) {
  test::TempDir tmp("intrinsics_prior_rule");
  DatasetIndex index;
  index.width = index.height = 480;
  // A 480-pixel unified fisheye (f 190, ξ 1.05): its corner pixels lie 127° from the axis.
  DatasetRunOptions run = runWithCalibration(tmp.path() / "ucm.txt",
                                             "UCM 190 190 239.5 239.5 1.05\n480 480\nnone\n480 480\n");
  OdometryOptions options;
  EXPECT_NEAR(viewWidthDeg(index, run), 254.0, 0.5);
  const std::string note = applyIntrinsicsPrior(index, run, &options);
  EXPECT_EQ(options.window.intrinsics_prior_weight, 0.0);
  EXPECT_NE(note.find("hemisphere"), std::string::npos) << note;

  // The same lens masked to 179° or cropped to a 90° pinhole (corner to corner
  // 2 atan(√2 · 239.5 / 240) = 109.4°), and the same lens with its intrinsics fixed.
  for (const std::string model : {"native-fov:179", "pinhole-crop:90"}) {
    run.camera_model = model;
    OdometryOptions held;
    EXPECT_EQ(applyIntrinsicsPrior(index, run, &held), "") << model;
    EXPECT_EQ(held.window.intrinsics_prior_weight, kDsoPrior) << model;
  }
  EXPECT_NEAR(viewWidthDeg(index, run), 2.0 * std::atan(std::sqrt(2.0) * 239.5 / 240.0) * 180.0 / M_PI,
              0.05);
  run.camera_model = "native-fov:180";
  EXPECT_DOUBLE_EQ(viewWidthDeg(index, run), 180.0);
  run.camera_model = "native";
  OdometryOptions fixed;
  fixed.window.optimize_intrinsics = false;
  EXPECT_EQ(applyIntrinsicsPrior(index, run, &fixed), "");
  EXPECT_EQ(fixed.window.intrinsics_prior_weight, kDsoPrior);

  // A 90° pinhole as the dataset's own camera (f = 240 on 480 pixels).
  run = runWithCalibration(tmp.path() / "pinhole.txt", "Pinhole 240 240 239.5 239.5 0\n480 480\nnone\n480 480\n");
  OdometryOptions pinhole;
  EXPECT_EQ(applyIntrinsicsPrior(index, run, &pinhole), "");
  EXPECT_EQ(pinhole.window.intrinsics_prior_weight, kDsoPrior);
}

// The width is the content's: the same fisheye frames blacked out beyond 70° from the axis (an
// image circle that shows less than its calibration could) keep the prior.
TEST(IntrinsicsPriorRule, TheImageContentBoundsTheView) {
  test::TempDir tmp("intrinsics_prior_content");
  const fs::path data = tmp.path() / "data";
  synth::SyntheticSequence sequence(test::smallSequenceConfig(3));
  synth::writeSyntheticDataset(sequence, data.string());
  const DatasetIndex full = openDataset(data.string());
  DatasetRunOptions run;
  const double full_width = viewWidthDeg(full, run);
  EXPECT_NEAR(full_width, 221.0, 0.5);  // the render fills its frame: corners 110° off the axis
  OdometryOptions options;
  EXPECT_NE(applyIntrinsicsPrior(full, run, &options), "");
  EXPECT_EQ(options.window.intrinsics_prior_weight, 0.0);

  const Camera camera = synth::datasetCamera(full, "");
  for (const DatasetFrame& frame : full.frames) {
    ImageU8 image = readImageU8(frame.image_path);
    for (int v = 0; v < image.height(); ++v)
      for (int u = 0; u < image.width(); ++u) {
        Eigen::Vector3d bearing;
        if (!camera.unproject(Eigen::Vector2d(u, v), bearing) ||
            std::acos(bearing.normalized().z()) > 70.0 * M_PI / 180.0)
          image(u, v) = 0;
      }
    writeImage(frame.image_path, image);
  }
  const DatasetIndex circled = openDataset(data.string());
  const double circled_width = viewWidthDeg(circled, run);
  EXPECT_NEAR(circled_width, 140.0, 2.5);  // a pixel of this 96-pixel fisheye spans 2.4° of view
  OdometryOptions held;
  EXPECT_EQ(applyIntrinsicsPrior(circled, run, &held), "");
  EXPECT_EQ(held.window.intrinsics_prior_weight, kDsoPrior);
}

}  // namespace
}  // namespace omnidso::cli
