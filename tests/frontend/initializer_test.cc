// The two-frame photometric initialiser on rendered fisheye sequences: it waits while there
// is no parallax — without letting unobservable distances drag the pose away — and
// initialises once the camera has translated enough.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>
#include <omnidso/core/error.hpp>
#include <omnidso/frontend/initializer.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace {

constexpr double kBlurSigmaPx = 1.0;  // a lens-like blur, as in the window tests

struct Initialisation {
  InitializationResult result;
  SE3d truth;  // T_frame_first of the last frame fed
  std::string status;
  int frames = 0;  // fed after the first
};

// Feeds the frames at start · path(k), k = 1 … max_frames, until the initialiser is done.
Initialisation initialiseAlong(const Camera& camera, const test::RenderedScene& scene, int levels,
                               int max_frames, const std::function<SE3d(const SE3d&, int)>& path,
                               const InitializerOptions& options = {}) {
  const SE3d start = scene.centralPose();
  Initializer initializer(camera, validityMask(camera), options);
  initializer.setFirstFrame(scene.renderPyramid(start, levels, kBlurSigmaPx), 1.0);
  Initialisation out;
  for (int k = 1; k <= max_frames && !out.result.done; ++k) {
    const SE3d pose = path(start, k);
    out.result = initializer.addFrame(*scene.renderPyramid(pose, levels, kBlurSigmaPx), 1.0);
    out.truth = pose.inverse() * start;
    out.frames = k;
  }
  out.status = initializer.status();
  return out;
}

double rotationErrorDeg(const Initialisation& init) {
  return so3Log(init.result.T_frame_first.rotation().conjugate() * init.truth.rotation()).norm() *
         180 / M_PI;
}

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
  const Initialisation init = initialiseAlong(camera, scene, 5, 20, [](const SE3d& s, int k) {
    return test::moveInCamera(s, {0.015 * k, 0.0, 0.005 * k}, {0.0, 0.3 * k, 0.0});
  });
  const InitializationResult& result = init.result;
  ASSERT_TRUE(result.done) << init.status;

  // Direction of the translation: the monocular scale is arbitrary, the direction is not.
  // Parallax of ≈ 10 px on 1000-odd points pins it to within a few degrees.
  const double cos_angle = result.T_frame_first.translation().normalized().dot(
      init.truth.translation().normalized());
  EXPECT_GT(cos_angle, std::cos(5.0 * M_PI / 180.0));
  const double rotation_error_deg = rotationErrorDeg(init);
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

// A hand-held camera that starts with a fast swing: the first frame is turned by 7° about
// two axes (9.9°), the next ones by 0.3° more each, with 2 cm of translation per frame,
// seen through a 90° pinhole (DSO's crop, where a rotation and a translation look most
// alike). At the coarsest level the first frame is displaced by ≈ 3.5 px, beyond the
// alignment's basin from the identity, and the constant-velocity prediction overshoots the
// second; the initialiser must start from its rotation search (initializer.hpp). Without
// the search it settles in a wrong basin and never initialises (D2 of the development set:
// initialised with rotation errors of 17–25°).
TEST(Initializer, TracksAFastSwingFromTheFirstFrame) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  // The pixel criterion alone: the subject is the start of each frame, and the ten frames end
  // at a triangulation angle of 3.1°, short of min_parallax_deg.
  InitializerOptions options;
  options.min_parallax_deg = 0.0;
  const Initialisation init = initialiseAlong(camera, scene, 4, 10, [](const SE3d& s, int k) {
    const double turn_deg = 7.0 + 0.3 * k;
    return test::moveInCamera(s, {0.02 * k, 0.0, 0.0}, {turn_deg, turn_deg, 0.0});
  }, options);
  ASSERT_TRUE(init.result.done) << init.status;
  const double rotation_error_deg = rotationErrorDeg(init);
  std::cout << init.status << "; rotation error " << rotation_error_deg << " deg\n";
  // 0.11° measured; a wrong basin is off by degrees.
  EXPECT_LT(rotation_error_deg, 0.3);
}

// A camera moving forward fast while turning, through a 90° pinhole: 0.25–0.3 m per frame
// toward a wall ≈ 4 m ahead, turning 1.9–2.4° per frame about all three axes; the initialiser
// snaps at the second frame. Before the snap the translation is penalised, and the pinhole
// reads a shift across the view as a turn: on the first scene the pre-snap pose was turned 5°
// about x and its translation tilted 23° toward y; the snap's solve from there stopped
// halfway, 3.9° off in rotation and 22° in the direction of travel (photometric error 9.1).
// From the pure forward translation (InitializerOptions::snap_translation_starts) it reaches
// the truth (6.1). The second scene, larger and with another texture seed, failed the same
// way (3.5° and 26°). Of 118 such starts (two image sizes, three texture seeds, steps of
// 0.1–0.4 m forward and back, turns of 0–2.9° per frame) three failed so, all fixed by the
// translation starts; one more switched, to a slightly lower error; the rest were unchanged.
// The 10 Hz holdout path H10 (docs/performance.md, "The snap's translation starts") is the
// field case.
TEST(Initializer, FindsTheTranslationAtTheSnapWhenTheViewReadItAsATurn) {
  struct Case {
    int size;
    std::uint64_t seed;
    double step_m;
    double turn_scale;
  };
  for (const Case& c : {Case{320, 3, 0.3, 2.0}, Case{480, 11, 0.25, 2.5}}) {
    SCOPED_TRACE("size " + std::to_string(c.size) + ", seed " + std::to_string(c.seed));
    const Camera camera = synth::syntheticCamera("pinhole", 90.0, c.size, c.size);
    const test::RenderedScene scene(camera, c.seed);
    const Initialisation init = initialiseAlong(camera, scene, 5, 8, [&](const SE3d& s, int k) {
      const double t = c.turn_scale * k;
      return test::moveInCamera(s, {0.02 * c.step_m * k, 0.0, c.step_m * k},
                                {-0.35 * t, 0.85 * t, 0.25 * t});
    });
    ASSERT_TRUE(init.result.done) << init.status;
    const double rotation_error_deg = rotationErrorDeg(init);
    const double direction_error_deg =
        std::acos(std::min(1.0, init.result.T_frame_first.translation().normalized().dot(
                                    init.truth.translation().normalized()))) * 180 / M_PI;
    std::cout << init.status << "; rotation error " << rotation_error_deg
              << " deg, direction error " << direction_error_deg << " deg\n";
    // Measured 0.05° and 0.3°, 0.06° and 0.3°; over the 118 starts the right basin gave at
    // most 0.24° and 1.1°, the wrong one 3.2–3.9° and 16–26°.
    EXPECT_LT(rotation_error_deg, 0.5);
    EXPECT_LT(direction_error_deg, 3.0);
  }
}

// Lost: without the rotation search a swing of 7° per frame about two axes carries the
// estimate where no point of the first frame projects any more. The initialiser must say so
// and keep waiting; it once read past its validity mask here and crashed.
// On the Ceres path: a lost alignment is chaotic — rounding-level changes grow by ≈ 1e7 per
// level (Ceres against itself from starts 1e-14 apart), so which points the wandering
// estimate keeps is a matter of the last bits. Measured over 84 exposures 1 + k·1e-15
// (session 13): Ceres ended with 0 points in 70 and (falsely) initialised in 11, the
// native solve in 66 and 19; the unperturbed exposure happens to give Ceres the outcome
// below and the native solve a false initialisation at frame 8 (55 points, RMSE 13.8). The
// run here pins the crash and the message; that a lost initialiser can accept a wrong
// alignment is a limitation of its acceptance test (docs/status.md), not of either solver.
TEST(Initializer, WaitsWhenNoPointProjectsAnyMore) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  InitializerOptions options;
  options.rotation_search_half_width = 0;
  options.native_solver = false;
  Initializer initializer(camera, validityMask(camera), options);
  initializer.setFirstFrame(scene.renderPyramid(start, 4, kBlurSigmaPx), 1.0);
  for (int k = 1; k <= 10; ++k) {
    const SE3d pose = test::moveInCamera(start, {0.02 * k, 0.0, 0.0}, {7.0 * k, 7.0 * k, 0.0});
    EXPECT_FALSE(initializer.addFrame(*scene.renderPyramid(pose, 4, kBlurSigmaPx), 1.0).done)
        << "frame " << k << ": " << initializer.status();
  }
  EXPECT_NE(initializer.status().find(" 0 points"), std::string::npos) << initializer.status();
}

// The coarse levels take one point per level pixel (InitializerOptions::level_cell_px): the
// level-0 selection crowds a 20 × 20 level 4 with several points per pixel, all of which
// entered its problem and the rotation search before. With cells of one pixel a level's
// problem can hold no more points than the level has pixels; level 0 keeps every point, and
// a coarse level keeps at least one point in every pixel the selection reaches — so it
// still holds most of level 1's points, whose pixels the selection rarely shares.
TEST(Initializer, CoarseLevelsTakeOnePointPerLevelPixel) {
  const Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  const std::shared_ptr<const ImagePyramid> first = scene.renderPyramid(start, 5, kBlurSigmaPx);
  const ImagePyramid frame =
      *scene.renderPyramid(test::moveInCamera(start, {0.02, 0.0, 0.0}, {1.0, 0.5, 0.0}), 5, kBlurSigmaPx);
  std::vector<int> points_per_level[2];  // [cell 0 | cell 1][level]
  for (const double cell : {0.0, 1.0}) {
    InitializerOptions options;
    options.level_cell_px = cell;
    Initializer initializer(camera, validityMask(camera), options);
    initializer.setFirstFrame(first, 1.0);
    for (int level = 0; level < 5; ++level) {
      InitializerState state = initializer.state();
      points_per_level[static_cast<int>(cell)].push_back(
          initializer.solveLevel(frame, 1.0, level, false, &state).num_points);
    }
  }
  const std::vector<int>& all = points_per_level[0];
  const std::vector<int>& one_per_pixel = points_per_level[1];
  std::cout << "points per level, every point: " << all[0] << " " << all[1] << " " << all[2] << " "
            << all[3] << " " << all[4] << "; one per pixel: " << one_per_pixel[0] << " "
            << one_per_pixel[1] << " " << one_per_pixel[2] << " " << one_per_pixel[3] << " "
            << one_per_pixel[4] << "\n";
  ASSERT_GT(all[0], 500);
  EXPECT_EQ(one_per_pixel[0], all[0]);
  EXPECT_GT(one_per_pixel[1], all[1] * 3 / 4);
  for (int level = 1; level < 5; ++level) {
    const int pixels = frame.level(level).width() * frame.level(level).height();
    EXPECT_LE(one_per_pixel[level], pixels) << "level " << level;
    EXPECT_LE(one_per_pixel[level], all[level]) << "level " << level;
  }
  EXPECT_GT(all[4], frame.level(4).width() * frame.level(4).height());  // crowded without it
}

// The triangulation angle (InitializerOptions::min_parallax_deg): through a 90° pinhole a
// sideways step of 1.5 cm per frame reaches the pixel criterion (6.4 px here) before its rays
// have turned by 5°; the initialiser then waits for the angle. The angle it reports is the RMS
// of ∠(b, b + d t) over its points, and the truth's — the true distances and translation at
// the same pixels — agrees with it to the accuracy of the estimate (the distances' deviation
// is bounded by 15 % in InitialisesFromTranslationWithTrueDirectionAndDistances; the RMS over
// a thousand points is tighter).
TEST(Initializer, WaitsForTheTriangulationAngle) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  const auto path = [](const SE3d& s, int k) {
    return test::moveInCamera(s, {0.015 * k, 0.0, 0.0}, {0.0, 0.2 * k, 0.0});
  };
  InitializerOptions pixels_only;
  pixels_only.min_parallax_deg = 0.0;
  const Initialisation by_pixels = initialiseAlong(camera, scene, 4, 30, path, pixels_only);
  const Initialisation by_angle = initialiseAlong(camera, scene, 4, 30, path);
  ASSERT_TRUE(by_pixels.result.done) << by_pixels.status;
  ASSERT_TRUE(by_angle.result.done) << by_angle.status;
  std::cout << "pixels only: " << by_pixels.status << "\nwith the angle: " << by_angle.status
            << "\n";
  EXPECT_LT(by_pixels.result.parallax_deg, InitializerOptions().min_parallax_deg);
  EXPECT_GE(by_angle.result.parallax_deg, InitializerOptions().min_parallax_deg);
  EXPECT_GT(by_angle.frames, by_pixels.frames);

  double sum = 0.0;
  int n = 0;
  const Eigen::Vector3d t = by_angle.truth.translation();
  for (const Eigen::Vector2d& pixel : by_angle.result.pixels) {
    Eigen::Vector3d b;
    if (!camera.unproject(pixel, b)) continue;
    const auto rho = scene.distance(start, b);
    if (!rho) continue;
    const Eigen::Vector3d moved = b + t / *rho;
    const double angle = std::atan2(b.cross(moved).norm(), b.dot(moved));
    sum += angle * angle;
    ++n;
  }
  ASSERT_GT(n, 300);
  const double true_deg = std::sqrt(sum / n) * 180.0 / M_PI;
  std::cout << "angle " << by_angle.result.parallax_deg << "° estimated, " << true_deg
            << "° true\n";
  EXPECT_NEAR(by_angle.result.parallax_deg / true_deg, 1.0, 0.1);
}

// The snap's own angle (InitializerOptions::snap_parallax_deg): on the same sideways path the
// translation is freed once the rays have turned by 2°, the snapped problem is refined frame
// after frame, and the initialiser still accepts only at min_parallax_deg — with the rotation
// and the translation's direction as accurate as when both come on one frame. Which of the two
// finds the right basin in a fast turn through a narrow view differs from render to render
// (docs/performance.md, "The initial pair's basin through a narrow view"); the odometry races
// them (odometry.hpp, InitializationRaceOptions).
TEST(Initializer, SnapsAtItsOwnAngleAndAcceptsAtTheTriangulationAngle) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const auto path = [](const SE3d& s, int k) {
    return test::moveInCamera(s, {0.015 * k, 0.0, 0.0}, {0.0, 0.2 * k, 0.0});
  };
  InitializerOptions early;
  early.snap_parallax_deg = 2.0;
  const Initialisation together = initialiseAlong(camera, scene, 4, 30, path);
  const Initialisation apart = initialiseAlong(camera, scene, 4, 30, path, early);
  ASSERT_TRUE(together.result.done) << together.status;
  ASSERT_TRUE(apart.result.done) << apart.status;
  std::cout << "snap at the angle: " << together.status << "\nsnap at 2°: " << apart.status
            << "\n";
  // Together: the snap is the frame that reaches both criteria, the accepted one.
  EXPECT_EQ(together.result.snapped_at, together.frames);
  // Apart: snapped where the rays had turned by about 2° (the sideways step adds ≈ 0.23° a
  // frame here), well before acceptance, which still waits for the angle.
  EXPECT_LT(apart.result.snapped_at, apart.frames - 3);
  EXPECT_GE(apart.result.parallax_deg, InitializerOptions().min_parallax_deg);
  EXPECT_GE(apart.frames, together.frames - 1);
  for (const Initialisation* init : {&together, &apart}) {
    const double direction_error_deg =
        std::acos(std::min(1.0, init->result.T_frame_first.translation().normalized().dot(
                                    init->truth.translation().normalized()))) * 180 / M_PI;
    std::cout << "rotation error " << rotationErrorDeg(*init) << " deg, direction error "
              << direction_error_deg << " deg\n";
    // As FindsTheTranslationAtTheSnapWhenTheViewReadItAsATurn: the right basin is within
    // tenths of a degree and one or two degrees of direction, a wrong one degrees and tens.
    EXPECT_LT(rotationErrorDeg(*init), 0.3);
    EXPECT_LT(direction_error_deg, 2.0);
  }
}

// The acceptance bound follows the pair's own error floor (InitializerOptions::
// max_rmse_growth). Sensor noise of σ = 18 intensity units, drawn anew for every frame, puts
// even a right alignment's error above the absolute bound of 15 (measured 17.0–17.2; the
// gradient weight w = c² / (c² + ‖∇I‖²) takes part of the two images' √2 σ), as the error floor
// of 18–20 of a car-like render did (docs/performance.md, "The initialiser's error bound"),
// where the initialiser accepted no right pair. With the bound absolute (growth 0) it waits
// through every frame; referred to the least error of the frames aligned before the snap, it
// accepts once the angle suffices, in the right basin.
TEST(Initializer, AcceptsAPairWhoseOwnErrorFloorIsAboveTheAbsoluteBound) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const SE3d start = scene.centralPose();
  const auto path = [&](int k) {
    return test::moveInCamera(start, {0.03 * k, 0.0, 0.0}, {0.0, 0.2 * k, 0.0});
  };
  const auto noisy = [&](const SE3d& pose, int k) {
    ImageF image = scene.render(pose, kBlurSigmaPx);
    std::mt19937 random(1000 + k);
    std::normal_distribution<float> noise(0.0f, 18.0f);
    for (size_t i = 0; i < image.size(); ++i) image.data()[i] += noise(random);
    return std::make_shared<const ImagePyramid>(image, 4);
  };
  InitializerOptions absolute;
  absolute.max_rmse_growth = 0.0;
  for (const InitializerOptions& options : {absolute, InitializerOptions()}) {
    Initializer initializer(camera, validityMask(camera), options);
    initializer.setFirstFrame(noisy(start, 0), 1.0);
    InitializationResult result;
    int k = 0;
    double least_rmse = std::numeric_limits<double>::infinity();
    while (!result.done && k < 16) {
      ++k;
      result = initializer.addFrame(*noisy(path(k), k), 1.0);
      least_rmse = std::min(least_rmse, result.rmse);
    }
    std::cout << "growth " << options.max_rmse_growth << ": " << initializer.status() << "\n";
    // The floor is the noise's: no frame, before the snap or after, comes below the bound.
    EXPECT_GT(least_rmse, options.max_rmse);
    if (options.max_rmse_growth == 0.0) {
      EXPECT_FALSE(result.done);
      continue;
    }
    ASSERT_TRUE(result.done) << initializer.status();
    const SE3d truth = path(k).inverse() * start;
    const double rotation_error_deg =
        so3Log(result.T_frame_first.rotation().conjugate() * truth.rotation()).norm() * 180 / M_PI;
    const double direction_error_deg =
        std::acos(std::min(1.0, result.T_frame_first.translation().normalized().dot(
                                    truth.translation().normalized()))) * 180 / M_PI;
    std::cout << "rotation error " << rotation_error_deg << " deg, direction error "
              << direction_error_deg << " deg\n";
    // As SnapsAtItsOwnAngleAndAcceptsAtTheTriangulationAngle, with room for the noise.
    EXPECT_LT(rotation_error_deg, 0.5);
    EXPECT_LT(direction_error_deg, 3.0);
  }
}

TEST(Initializer, RefusesAGrowthOfTheErrorBoundThatIsNegativeOrNotFinite) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 64, 64);
  for (const double growth : {-0.5, std::numeric_limits<double>::infinity(),
                              std::numeric_limits<double>::quiet_NaN()}) {
    InitializerOptions options;
    options.max_rmse_growth = growth;
    EXPECT_THROW(Initializer initializer(camera, validityMask(camera), options), Error) << growth;
  }
}

// The tracker's first velocity (InitializationResult::T_frame_previous): one frame's motion,
// not the whole initialisation's. The camera turns faster and faster (0.02 k² degrees at frame
// k) while stepping 1.5 cm sideways per frame, so the last step turns about twice the mean one.
// - Rotation: the last step's. The frame before was aligned before the snap, where the
//   translation penalty leaves part of the sideways step in the rotation (0.16° through this
//   90° view), so the bound is half the gap between the last and the mean step: closer to the
//   last. The whole initialisation's turn, which the odometry had used, is ≈ k times the mean.
// - Translation: the mean step's, 1 / k of the whole in the same scale (within 5 %; the path
//   steps evenly), along the chord: turned from the last step's direction by about half the
//   total rotation.
// On D2's crop, seed 4, the old prediction carried ten frames' turn and tracking was lost on
// the first frame after initialisation (docs/performance.md, "The tracker's first velocity").
TEST(Initializer, ReportsOneFramesMotionForTheTrackersFirstVelocity) {
  const Camera camera = synth::syntheticCamera("pinhole", 90.0, 320, 320);
  const test::RenderedScene scene(camera, 3);
  const auto path = [](const SE3d& s, int k) {
    return test::moveInCamera(s, {0.015 * k, 0.0, 0.0}, {0.0, 0.02 * k * k, 0.0});
  };
  const Initialisation init = initialiseAlong(camera, scene, 4, 30, path);
  ASSERT_TRUE(init.result.done) << init.status;
  const int k = init.frames;
  ASSERT_GE(k, 8) << "too few frames for the last step to differ from the mean one";
  const SE3d start = scene.centralPose();
  const SE3d true_step = path(start, k).inverse() * path(start, k - 1);  // T_k_(k−1)
  const double step_deg = so3Log(true_step.rotation()).norm() * 180 / M_PI;
  const double mean_step_deg = so3Log(init.truth.rotation()).norm() * 180 / M_PI / k;
  const SE3d& estimate = init.result.T_frame_previous;
  const double rotation_error_deg =
      so3Log(estimate.rotation().conjugate() * true_step.rotation()).norm() * 180 / M_PI;
  const double length_ratio = estimate.translation().norm() /
                              init.result.T_frame_first.translation().norm() * k;
  const double cos_angle =
      estimate.translation().normalized().dot(true_step.translation().normalized());
  std::cout << "initialised after " << k << " frames; last step " << step_deg << "° (mean "
            << mean_step_deg << "°), its rotation error " << rotation_error_deg
            << "°; translation k·|t_step| / |t| = " << length_ratio << ", direction error "
            << std::acos(std::min(1.0, cos_angle)) * 180 / M_PI << "°\n";
  ASSERT_GT(step_deg - mean_step_deg, 0.25);
  EXPECT_LT(rotation_error_deg, 0.5 * (step_deg - mean_step_deg));
  EXPECT_NEAR(length_ratio, 1.0, 0.05);
  const double total_deg = mean_step_deg * k;
  EXPECT_GT(cos_angle, std::cos((0.5 * total_deg + 1.0) * M_PI / 180.0));
}

}  // namespace
}  // namespace omnidso
