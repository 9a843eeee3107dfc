// The epipolar-curve search (paper Sec. V-B) on a rendered fisheye pair with known distances,
// and its interval on a striped plane whose stripes cross the curve at a known angle.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include <omnidso/core/error.hpp>
#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

struct SearchStats {
  int searched = 0, good = 0, interval_holds_truth = 0, match_within_half_pixel = 0;
  int good_behind_camera = 0;  // bearings with z < 0: more than 90° off the optical axis
};

SearchStats searchPair(const Camera& camera, const Eigen::Vector3d& baseline,
                       int pattern_spread = 1) {
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
    if (!makeImmaturePoint(camera, host.level(0), host.gradients(0), 0, p.pixel.cast<double>(),
                           &point, pattern_spread))
      continue;
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

// The pattern on steps of two pixels (OdometryOptions::pattern_spread) searches as well.
TEST(EpipolarSearch, SpreadPatternFindsTrueDistance) {
  const Camera camera = synth::syntheticCamera("ucm", 195.0, 320, 320);
  expectAccurate(searchPair(camera, {0.12, 0.02, 0.05}, 2));
}

TEST(EpipolarSearch, PureRotationHasNothingToSearch) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 160, 160);
  const test::RenderedScene scene(camera, 3);
  const SE3d T = scene.centralPose();
  const ImagePyramid target(scene.render(test::moveInCamera(T, {0, 0, 0}, {0, 3, 0})), 2);
  ImmaturePoint point;
  ASSERT_TRUE(
      makeImmaturePoint(camera, target.level(0), target.gradients(0), 0, {80, 80}, &point));
  const SE3d rotation_only = test::moveInCamera(SE3d(), {0, 0, 0}, {0, 3, 0}).inverse();
  const TraceResult r = traceImmaturePoint(point, camera, rotation_only, target.level(0),
                                           target.gradients(0), AffineTransfer{},
                                           EpipolarSearchOptions{});
  EXPECT_EQ(r.status, TraceStatus::kSkipped);
  EXPECT_EQ(point.d_min, 0.0);
  EXPECT_TRUE(std::isinf(point.d_max));
}

// A fronto-parallel plane at depth z_plane textured with straight stripes,
// I = 128 + 60 sin(2π (x cos α + y sin α) / 36) in the host's pixels (x, y): every gradient points
// along (cos α, sin α), at the angle α to a horizontal epipolar line. The target camera sits
// 0.05 m to the right; its image is rendered through the camera model, so the pair is exact.
struct StripedPlanePair {
  Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 240);
  double z_plane = 1.0;
  SE3d T_target_host = SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.05, 0.0, 0.0));
  ImagePyramid host, target;

  explicit StripedPlanePair(double alpha_deg)
      : host(render(alpha_deg, SE3d()), 2), target(render(alpha_deg, T_target_host), 2) {}

  ImageF render(double alpha_deg, const SE3d& T_cam_host) const {
    const double alpha = alpha_deg * M_PI / 180.0;
    const SE3d T_host_cam = T_cam_host.inverse();
    ImageF image(camera.width(), camera.height());
    for (int v = 0; v < image.height(); ++v)
      for (int u = 0; u < image.width(); ++u) {
        Eigen::Vector3d b;
        if (!camera.unproject(Eigen::Vector2d(u, v), b)) continue;
        const Eigen::Vector3d c = T_host_cam.translation();
        const Eigen::Vector3d r = T_host_cam.rotationMatrix() * b;
        const Eigen::Vector3d x = c + r * ((z_plane - c.z()) / r.z());  // on the plane
        Eigen::Vector2d uh;
        if (!camera.project(x, uh)) continue;
        image(u, v) = static_cast<float>(
            128.0 + 60.0 * std::sin(2.0 * M_PI *
                                    (uh.x() * std::cos(alpha) + uh.y() * std::sin(alpha)) / 36.0));
      }
    return image;
  }
};

struct OffsetTrace {
  bool good = false;
  bool interval_holds_truth = false;
  double along_error_px = 0.0;  // match − truth, horizontal
  double interval_px = 0.0;
};

// Searches host pixel (u, v) on a curve moved offset_px down across itself: the tracked pose's
// rotation about the x axis is off by offset_px / f.
OffsetTrace traceWithOffset(const StripedPlanePair& pair, int u, int v, double offset_px,
                            const EpipolarSearchOptions& options) {
  OffsetTrace out;
  ImmaturePoint point;
  if (!makeImmaturePoint(pair.camera, pair.host.level(0), pair.host.gradients(0), 0, {u, v},
                         &point))
    return out;
  const double d_true = point.bearing.z() / pair.z_plane;  // 1 / ‖x‖ on the plane
  Eigen::Vector2d u_true;
  EXPECT_TRUE(pair.camera.project(pair.T_target_host * (point.bearing / d_true), u_true));
  const double f = pair.camera.params()[0];  // fx
  const SE3d searched =
      SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(-offset_px / f, Eigen::Vector3d::UnitX())),
           Eigen::Vector3d::Zero()) *
      pair.T_target_host;
  const TraceResult r = traceImmaturePoint(point, pair.camera, searched, pair.target.level(0),
                                           pair.target.gradients(0), AffineTransfer{}, options);
  out.good = r.status == TraceStatus::kGood;
  out.interval_holds_truth = point.d_min <= d_true && d_true <= point.d_max;
  out.along_error_px = r.match.x() - u_true.x();
  out.interval_px = point.last_interval_px;
  return out;
}

const std::vector<Eigen::Vector2i> kStripePixels = {{150, 110}, {160, 120}, {172, 128}, {140, 135}};

// Stripes at α = 60° to the curve and the curve 1 px off: the best match lies e tan α = 1.73 px
// along the curve from the truth (header comment: δ = −(c / a) ε). The interval must widen to
// σ + e tan α and so still hold the true distance; σ alone (curve_offset_px = 0) misses it.
TEST(EpipolarSearch, IntervalWidensWhenTheGradientCrossesTheCurve) {
  const StripedPlanePair pair(60.0);
  EpipolarSearchOptions options;
  ASSERT_EQ(options.curve_offset_px, 1.0);
  const double offset_px = options.curve_offset_px;
  const double tan_alpha = std::tan(60.0 * M_PI / 180.0);
  for (const Eigen::Vector2i& p : kStripePixels) {
    SCOPED_TRACE(testing::Message() << "pixel " << p.transpose());
    const OffsetTrace t = traceWithOffset(pair, p.x(), p.y(), offset_px, options);
    ASSERT_TRUE(t.good);
    // the geometry of the offset, to the sub-pixel refinement's and the difference gradients'
    // few hundredths of a pixel
    EXPECT_NEAR(std::abs(t.along_error_px), offset_px * tan_alpha, 0.1);
    // 2 (σ + e tan α'), α' the angle of the central differences' gradient (1.71 for 1.73)
    EXPECT_NEAR(t.interval_px, 2.0 * (options.match_sigma_px + offset_px * tan_alpha), 0.1);
    EXPECT_TRUE(t.interval_holds_truth);

    EpipolarSearchOptions sigma_only = options;
    sigma_only.curve_offset_px = 0.0;
    const OffsetTrace narrow = traceWithOffset(pair, p.x(), p.y(), offset_px, sigma_only);
    ASSERT_TRUE(narrow.good);
    EXPECT_DOUBLE_EQ(narrow.interval_px, 2.0 * options.match_sigma_px);
    EXPECT_FALSE(narrow.interval_holds_truth) << "the test's offset no longer shows the error";
  }
}

// Gradients along the curve (α = 0): an offset across it moves nothing, and the interval keeps
// the matching uncertainty alone — up to the small angle at which the search's pattern map (a
// patch facing the host, J_o) shows the plane's stripes: |c| / a ≈ |t_x| |v − c_y| / f ≤ 0.005
// at these pixels, so the interval is 2σ within 0.02 px.
TEST(EpipolarSearch, IntervalStaysNarrowWhenTheGradientFollowsTheCurve) {
  const StripedPlanePair pair(0.0);
  const EpipolarSearchOptions options;
  for (const Eigen::Vector2i& p : kStripePixels) {
    SCOPED_TRACE(testing::Message() << "pixel " << p.transpose());
    const OffsetTrace t = traceWithOffset(pair, p.x(), p.y(), options.curve_offset_px, options);
    ASSERT_TRUE(t.good);
    EXPECT_NEAR(t.along_error_px, 0.0, 0.05);
    EXPECT_NEAR(t.interval_px, 2.0 * options.match_sigma_px, 0.02);
    EXPECT_TRUE(t.interval_holds_truth);
  }
}

// A negative offset would shrink the interval below σ, and past zero turn it inside out: the
// odometry refuses it, naming the setting.
TEST(EpipolarSearch, OdometryRefusesANegativeCurveOffset) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 240);
  OdometryOptions options;
  options.epipolar.curve_offset_px = -1.0;
  try {
    Odometry odometry(camera, options);
    FAIL() << "accepted curve_offset_px = -1";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("curve_offset_px"), std::string::npos) << e.what();
  }
  options.epipolar.curve_offset_px = 0.0;  // the fixed interval: allowed
  EXPECT_NO_THROW(Odometry(camera, options));
}

// The odometry refuses a pattern spread outside 1 … 8, naming the setting.
TEST(EpipolarSearch, OdometryRefusesAPatternSpreadOutOfRange) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 240);
  OdometryOptions options;
  for (int spread : {0, 9}) {
    options.pattern_spread = spread;
    try {
      Odometry odometry(camera, options);
      FAIL() << "accepted pattern_spread = " << spread;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("pattern_spread"), std::string::npos) << e.what();
    }
  }
  options.pattern_spread = 2;
  EXPECT_NO_THROW(Odometry(camera, options));
}

}  // namespace
}  // namespace omnidso
