// The epipolar-curve search (paper Sec. V-B) on a rendered fisheye pair with known distances.
#include <gtest/gtest.h>

#include <iostream>

#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

struct SearchStats {
  int searched = 0, good = 0, interval_holds_truth = 0, match_within_half_pixel = 0;
  int good_behind_camera = 0;  // bearings with z < 0: more than 90° off the optical axis
};

SearchStats searchPair(const Camera& camera, const Eigen::Vector3d& baseline) {
  const test::RenderedScene scene(camera, 7);
  const SE3d T_world_host = scene.centralPose();
  const SE3d T_world_target = test::moveInCamera(T_world_host, baseline, {0.0, 2.0, 1.0});
  const ImagePyramid host(scene.render(T_world_host), 3);
  const ImagePyramid target(scene.render(T_world_target), 3);
  const SE3d T_target_host = T_world_target.inverse() * T_world_host;

  PixelSelectorOptions selection;
  selection.desired_points = 600;
  const std::vector<SelectedPixel> pixels = selectPixels(host, validityMask(camera), selection);
  EpipolarSearchOptions options;
  options.max_search_px = 150.0;  // the first search covers the whole [0, ∞) interval

  SearchStats stats;
  for (const SelectedPixel& p : pixels) {
    ImmaturePoint point;
    if (!makeImmaturePoint(camera, host.level(0), 0, p.pixel.cast<double>(), &point)) continue;
    const auto rho = scene.distance(T_world_host, point.bearing);
    if (!rho) continue;
    const double d_true = 1.0 / *rho;
    Eigen::Vector2d u_true;
    if (!camera.project(T_target_host * (point.bearing * *rho), u_true)) continue;
    ++stats.searched;
    const TraceResult r = traceImmaturePoint(point, camera, T_target_host, target.level(0),
                                             target.gradients(0), AffineTransfer{}, options);
    if (r.status != TraceStatus::kGood) continue;
    ++stats.good;
    if (point.d_min <= d_true && d_true <= point.d_max) ++stats.interval_holds_truth;
    if ((r.match - u_true).norm() < 0.5) ++stats.match_within_half_pixel;
    if (point.bearing.z() < 0) ++stats.good_behind_camera;
  }
  return stats;
}

// Noise-free images and a true pattern: the only failures are occlusion boundaries (the
// pattern straddles two surfaces at different distances) and texture that repeats along the
// curve; so a large majority — not all — of the unambiguous matches must be right.
void expectAccurate(const SearchStats& s) {
  std::cout << "searched " << s.searched << ", good " << s.good << ", interval holds truth "
            << s.interval_holds_truth << ", match < 0.5 px " << s.match_within_half_pixel
            << ", good beyond 90 deg " << s.good_behind_camera << "\n";
  ASSERT_GT(s.searched, 200);
  EXPECT_GT(s.good, s.searched / 3) << "too few unambiguous matches";
  EXPECT_GE(s.interval_holds_truth, 0.85 * s.good)
      << s.interval_holds_truth << " of " << s.good << " intervals contain the truth";
  EXPECT_GE(s.match_within_half_pixel, 0.85 * s.good)
      << s.match_within_half_pixel << " of " << s.good << " matches within 0.5 px";
}

TEST(EpipolarSearch, UnifiedFisheyeBeyond180DegreesFindsTrueDistance) {
  const Camera camera = synth::syntheticCamera("ucm", 195.0, 320, 320);
  const SearchStats s = searchPair(camera, {0.12, 0.02, 0.05});
  expectAccurate(s);
  EXPECT_GT(s.good_behind_camera, 0) << "no match found more than 90 degrees off the axis";
}

TEST(EpipolarSearch, PinholeStraightLineUsesTheSameCodePath) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 240);
  expectAccurate(searchPair(camera, {0.12, 0.02, 0.05}));
}

TEST(EpipolarSearch, PureRotationHasNothingToSearch) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 160, 160);
  const test::RenderedScene scene(camera, 3);
  const SE3d T = scene.centralPose();
  const ImagePyramid target(scene.render(test::moveInCamera(T, {0, 0, 0}, {0, 3, 0})), 2);
  ImmaturePoint point;
  ASSERT_TRUE(makeImmaturePoint(camera, target.level(0), 0, {80, 80}, &point));
  const SE3d rotation_only = test::moveInCamera(SE3d(), {0, 0, 0}, {0, 3, 0}).inverse();
  const TraceResult r = traceImmaturePoint(point, camera, rotation_only, target.level(0),
                                           target.gradients(0), AffineTransfer{},
                                           EpipolarSearchOptions{});
  EXPECT_EQ(r.status, TraceStatus::kSkipped);
  EXPECT_EQ(point.d_min, 0.0);
  EXPECT_TRUE(std::isinf(point.d_max));
}

}  // namespace
}  // namespace omnidso
