// placeByReference (frame_placement.hpp): a frame tracked against a keyframe keeps its pose
// relative to that keyframe when the window moves the keyframe; the epipolar search then finds
// the true matches where the frame's world pose from before the move does not.
// poseInCurrentEstimate: the constant-velocity guess from two frames in one estimate.
#include <gtest/gtest.h>

#include <vector>

#include <omnidso/frontend/epipolar_search.hpp>
#include <omnidso/frontend/frame_placement.hpp>
#include <omnidso/frontend/odometry.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

TEST(FramePlacement, AnUnmovedReferenceGivesTheTrackersPlacementBitForBit) {
  // The deterministic mode maps each frame before the window changes: its trajectory must not
  // change by a bit.
  const SE3d T_world_reference = test::moveInCamera(SE3d(), {0.3, -0.2, 1.1}, {4.0, -7.0, 12.0});
  const SE3d T_frame_reference = test::moveInCamera(SE3d(), {-0.05, 0.02, 0.11}, {1.5, 0.3, -2.0});
  const SE3d placed = placeByReference(T_world_reference, T_frame_reference);
  const SE3d tracked = T_world_reference * T_frame_reference.inverse();  // as tracking computes it
  EXPECT_EQ(placed.matrix(), tracked.matrix());
}

struct SearchCount {
  int searched = 0, good = 0, match_within_half_pixel = 0;
};

// Host H and reference R are keyframes; the frame f was tracked against R with both in the old
// estimate (here the truth). The window then moves every keyframe by one rigid motion G, as a
// solve may. The search in f for H's points: with the true relative pose, with f placed by its
// reference, and with f's world pose as tracked (before the move).
enum class Placement { kTruth, kByReference, kAsTracked };

SearchCount searchAfterTheMove(Placement placement) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 240);
  const test::RenderedScene scene(camera, 11);
  const SE3d T_world_host = scene.centralPose();
  const SE3d T_world_reference = test::moveInCamera(T_world_host, {0.06, 0.01, 0.02}, {0, 1, 0});
  const SE3d T_world_frame = test::moveInCamera(T_world_reference, {0.06, -0.01, 0.03}, {0.5, 1, 0});
  const ImagePyramid host(scene.render(T_world_host), 3);
  const ImagePyramid frame(scene.render(T_world_frame), 3);

  const SE3d G = test::moveInCamera(SE3d(), {0.3, -0.1, 0.2}, {2.0, -3.0, 1.0});  // the move
  const SE3d T_world_host_after = G * T_world_host;
  const SE3d T_frame_host_true = T_world_frame.inverse() * T_world_host;
  SE3d T_world_frame_placed = T_world_frame;  // as tracked
  if (placement == Placement::kByReference)
    T_world_frame_placed =
        placeByReference(G * T_world_reference, T_world_frame.inverse() * T_world_reference);
  const SE3d T_frame_host = placement == Placement::kTruth
                                ? T_frame_host_true
                                : T_world_frame_placed.inverse() * T_world_host_after;

  PixelSelectorOptions selection;
  selection.desired_points = 500;
  EpipolarSearchOptions options;
  options.max_search_px = 150.0;
  SearchCount count;
  for (const SelectedPixel& p : selectPixels(host, validityMask(camera), selection)) {
    ImmaturePoint point;
    if (!makeImmaturePoint(camera, host.level(0), host.gradients(0), 0, p.pixel.cast<double>(),
                           &point))
      continue;
    const auto rho = scene.distance(T_world_host, point.bearing);
    Eigen::Vector2d u_true;
    if (!rho || !camera.project(T_frame_host_true * (point.bearing * *rho), u_true)) continue;
    ++count.searched;
    const TraceResult r = traceImmaturePoint(point, camera, T_frame_host, frame.level(0),
                                             frame.gradients(0), AffineTransfer{}, options);
    if (r.status != TraceStatus::kGood) continue;
    ++count.good;
    if ((r.match - u_true).norm() < 0.5) ++count.match_within_half_pixel;
  }
  return count;
}

TEST(FramePlacement, TheSearchAfterTheWindowMovedTheReferenceFindsTheTrueMatches) {
  const SearchCount truth = searchAfterTheMove(Placement::kTruth);
  const SearchCount placed = searchAfterTheMove(Placement::kByReference);
  const SearchCount stale = searchAfterTheMove(Placement::kAsTracked);
  RecordProperty("truth_good", truth.good);
  RecordProperty("truth_within_half_pixel", truth.match_within_half_pixel);
  RecordProperty("placed_good", placed.good);
  RecordProperty("placed_within_half_pixel", placed.match_within_half_pixel);
  RecordProperty("stale_within_half_pixel", stale.match_within_half_pixel);
  ASSERT_GT(truth.searched, 150);
  ASSERT_GT(truth.match_within_half_pixel, truth.searched / 3);
  // Placed by its reference, the frame's pose relative to the moved host is the true one up to
  // rounding (≈ 1e-15): the search must find what it finds with the truth.
  // Rounding can tip a match that sits exactly on one of the search's thresholds, nothing more.
  EXPECT_NEAR(placed.good, truth.good, 2);
  EXPECT_NEAR(placed.match_within_half_pixel, truth.match_within_half_pixel, 2);
  // With the pose from before the move the relative pose is off by the move (3.7° and 0.37 m:
  // the curves tens of pixels away): few true matches (what the real-time mode searched with
  // before).
  EXPECT_LT(stale.match_within_half_pixel, truth.match_within_half_pixel / 4);
}

FrameRecord trackedFrame(int index, bool is_keyframe, int reference, const SE3d& T_frame_ref) {
  FrameRecord f;
  f.index = index;
  f.tracked = true;
  f.is_keyframe = is_keyframe;
  f.reference_keyframe = reference;
  f.T_frame_ref = T_frame_ref;
  return f;
}

TEST(PoseInCurrentEstimate, AKeyframeIsTakenAtItsOwnPoseAnotherFrameByItsReference) {
  const SE3d T_world_3 = test::moveInCamera(SE3d(), {0.2, 0.1, -0.3}, {3.0, 1.0, -2.0});
  const SE3d T_world_4 = test::moveInCamera(T_world_3, {0.05, 0.0, -0.04}, {0.5, 6.0, 0.2});
  auto keyframe_pose = [&](int id) { return id == 3 ? T_world_3 : T_world_4; };
  // The keyframe's tracked T_frame_ref (against keyframe 3) is not used: the window's pose is.
  const SE3d tracked = test::moveInCamera(SE3d(), {0.01, 0.0, 0.02}, {0.1, 0.0, 0.0});
  EXPECT_EQ(poseInCurrentEstimate(trackedFrame(4, true, 3, tracked), keyframe_pose).matrix(),
            T_world_4.matrix());
  EXPECT_EQ(poseInCurrentEstimate(trackedFrame(5, false, 4, tracked), keyframe_pose).matrix(),
            placeByReference(T_world_4, tracked).matrix());
}

// The camera moves at constant velocity through keyframes P and L. P's estimate was off by a
// centimetre and 0.3° until L's solve corrected it (here to the truth), as solves do in a fast
// turn. The guess for the next frame is L · (L⁻¹ P)⁻¹: with P taken in the solve's estimate it
// is the true next pose; with P from before the solve (what the odometry used) it is off by the
// correction.
TEST(PoseInCurrentEstimate, TheConstantVelocityGuessAfterASolveThatMovedThePreviousKeyframe) {
  const SE3d step = test::moveInCamera(SE3d(), {0.03, -0.01, -0.05}, {0.5, 6.5, 0.3});
  const SE3d T_world_P = test::moveInCamera(SE3d(), {1.0, 0.2, 0.5}, {10.0, 40.0, -5.0});
  const SE3d T_world_L = T_world_P * step, T_world_next = T_world_L * step;
  const SE3d T_world_P_before = test::moveInCamera(T_world_P, {0.01, 0.0, 0.0}, {0.0, 0.3, 0.0});
  const FrameRecord P = trackedFrame(7, true, 6, SE3d());
  auto after_solve = [&](int id) { return id == 7 ? T_world_P : T_world_L; };

  auto guess = [&](const SE3d& T_world_prev) {
    const SE3d velocity = T_world_L.inverse() * T_world_prev;  // T_last_prev, as trackFrame
    return T_world_L * velocity.inverse();
  };
  const SE3d consistent = guess(poseInCurrentEstimate(P, after_solve));
  const SE3d stale = guess(T_world_P_before);
  const SE3d e_consistent = consistent.inverse() * T_world_next;
  const SE3d e_stale = stale.inverse() * T_world_next;
  EXPECT_LT(e_consistent.translation().norm(), 1e-12);
  EXPECT_LT(so3Log(e_consistent.rotation()).norm(), 1e-12);
  // The stale guess is off by the correction Δ seen from one step later, step⁻¹ Δ step: the
  // same 0.3°, and 1 cm up to (R_Δ − I) t_step, under 2 sin(0.15°) · 6 cm ≈ 0.3 mm.
  EXPECT_NEAR(e_stale.translation().norm(), 0.01, 0.35e-3);
  EXPECT_NEAR(so3Log(e_stale.rotation()).norm() * 180.0 / M_PI, 0.3, 1e-6);
}

}  // namespace
}  // namespace omnidso
