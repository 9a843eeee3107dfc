// The two-frame photometric initialiser on rendered fisheye sequences: it waits while there
// is no parallax — without letting unobservable distances drag the pose away — and
// initialises once the camera has translated enough.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

constexpr double kBlurSigmaPx = 1.0;  // a lens-like blur, as in the window tests

// A camera turning by 0.4° per frame about two axes and barely translating (1 mm per
// frame), as a hand-held camera does before the user starts walking. Distances are not
// observable, so the initialiser must not succeed; and the error of the alignment must stay
// at the level of the rendering itself. It did not when the inverse distances were only
// weakly tied together: they fitted aliasing and dragged the rotation, and the error grew
// past the acceptance bound (15) within ten frames.
TEST(Initializer, WaitsWithoutDriftingWhileTheCameraOnlyRotates) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  Initializer initializer(camera, validityMask(camera));
  initializer.setFirstFrame(scene.renderPyramid(start, 5, kBlurSigmaPx), 1.0);
  for (int k = 1; k <= 10; ++k) {
    const SE3d pose = test::moveInCamera(start, {0.001 * k, 0.0, 0.0}, {0.4 * k, 0.4 * k, 0.0});
    const InitializationResult r =
        initializer.addFrame(*scene.renderPyramid(pose, 5, kBlurSigmaPx), 1.0);
    EXPECT_FALSE(r.done) << "frame " << k << ": " << initializer.status();
    // The rendering limit is ≈ 2.5 intensity units RMS here (anti-aliasing against bilinear
    // interpolation, coarse_tracker_test.cc); 8 leaves room and is about half the acceptance
    // bound. With the old weak tie the error passed 9 at frame 5 and 22 by frame 7.
    EXPECT_LT(r.rmse, 8.0) << "frame " << k << ": " << initializer.status();
    if (k == 10) std::cout << initializer.status() << "\n";
  }
}

// Sideways translation of 1.5 cm per frame with a slow turn: the initialiser succeeds after
// a few frames, with the translation direction and the points' distances (up to the
// monocular scale) close to the truth.
TEST(Initializer, InitialisesFromTranslationWithTrueDirectionAndDistances) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  Initializer initializer(camera, validityMask(camera));
  initializer.setFirstFrame(scene.renderPyramid(start, 5, kBlurSigmaPx), 1.0);
  InitializationResult result;
  SE3d truth;
  for (int k = 1; k <= 20 && !result.done; ++k) {
    const SE3d pose = test::moveInCamera(start, {0.015 * k, 0.0, 0.005 * k}, {0.0, 0.3 * k, 0.0});
    result = initializer.addFrame(*scene.renderPyramid(pose, 5, kBlurSigmaPx), 1.0);
    truth = pose.inverse() * start;  // T_frame_first
  }
  ASSERT_TRUE(result.done) << initializer.status();

  // Direction of the translation: the monocular scale is arbitrary, the direction is not.
  // Parallax of ≈ 10 px on 1000-odd points pins it to within a few degrees.
  const double cos_angle = result.T_frame_first.translation().normalized().dot(
      truth.translation().normalized());
  EXPECT_GT(cos_angle, std::cos(5.0 * M_PI / 180.0));
  const double rotation_error_deg =
      so3Log(result.T_frame_first.rotation().conjugate() * truth.rotation()).norm() * 180 / M_PI;
  EXPECT_LT(rotation_error_deg, 0.2);

  // Distances up to one scale (the median ratio): the median deviation from it stays below
  // 15 %. Not tighter: points near the epipoles (along the baseline) have no parallax, and
  // the regulariser holds them near the mean; the window refines the rest later.
  std::vector<double> ratio;
  for (size_t i = 0; i < result.pixels.size(); ++i) {
    Eigen::Vector3d bearing;
    if (!camera.unproject(result.pixels[i], bearing)) continue;
    const auto rho = scene.distance(start, bearing);
    if (rho) ratio.push_back(result.inverse_distances[i] * *rho);
  }
  ASSERT_GT(ratio.size(), 300u);
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double scale = median(ratio);
  std::vector<double> deviation;
  for (double r : ratio) deviation.push_back(std::abs(r / scale - 1.0));
  const double median_deviation = median(deviation);
  std::cout << "direction error " << std::acos(std::min(1.0, cos_angle)) * 180 / M_PI
            << " deg, rotation error " << rotation_error_deg << " deg, median distance deviation "
            << median_deviation << " over " << ratio.size() << " points\n";
  EXPECT_LT(median_deviation, 0.15);
}

}  // namespace
}  // namespace omnidso
