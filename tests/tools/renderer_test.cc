// The renderer against the scene and the photometric model it defines.
#include <omnidso/synth/renderer.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <omnidso/synth/random.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>

namespace omnidso::synth {
namespace {

struct RenderFixture {
  RenderFixture()
      : camera(syntheticCamera("ucm", 185.0, 96, 96)),
        scene(makeRoomScene([] {
          RoomSceneConfig config;
          config.texel_size = 0.02;
          return config;
        }(), 21)),
        pose(levelCameraRotation(0.7), scene.freeSpace().centre()) {}
  Camera camera;
  Scene scene;
  SE3d pose;
};

Renderer makeRenderer(const RenderFixture& f, bool noise, int threads = 2,
                      std::uint64_t seed = 1) {
  PhotometricModel photometric;
  photometric.noise = noise;
  const Eigen::VectorXd p = f.camera.params();
  return Renderer(f.scene, makeBearingTable(f.camera, 96, 96, 2, p[2], p[3]), photometric,
                  threads, seed);
}

// The radiance the scene has along the ray through pixel position uv.
float radianceThrough(const RenderFixture& f, const Eigen::Vector2d& uv) {
  Eigen::Vector3d bearing;
  if (!f.camera.unproject(uv, bearing)) return -1.f;
  return f.scene.radianceAlong(f.pose.translation().cast<float>(),
                               (f.pose.rotation() * bearing).cast<float>());
}

// The intensity at the projection of a 3D scene point X equals G(gain·t·V·B(X)). Error
// bound: the bilinearly interpolated image at the projection (u, v) is a convex
// combination of the 4 surrounding pixels; each pixel is round(G(E_pixel)) with E_pixel the
// mean over its 2×2 samples of gain·t·V_pixel·B(sample). G is monotone, so the value lies in
// [G(E_min) − ½, G(E_max) + ½], E_min/E_max over those 16 samples; and so does G(E(X)) up to
// the vignette's change from the pixel centres to (u, v), included by evaluating V at (u, v)
// as well. Points are taken where this anti-aliasing bound is below 3 grey levels.
TEST(RendererTest, IntensityAtProjectedScenePointFollowsThePhotometricModel) {
  const RenderFixture f;
  const Renderer renderer = makeRenderer(f, /*noise=*/false);
  const PhotometricModel& model = renderer.photometric();
  const double exposure_ms = 9.0;
  const ImageU8 image = renderer.render({f.pose}, exposure_ms, 0);
  const double scale = model.gain_per_ms * exposure_ms;

  SeededRandom random(9);
  int tested = 0;
  int behind_camera = 0;
  for (int attempt = 0; attempt < 4000 && tested < 40; ++attempt) {
    // A scene point: the hit of a random ray from the camera centre.
    const Eigen::Vector3d direction_cam =
        Eigen::Vector3d(random.gaussian(), random.gaussian(), random.gaussian()).normalized();
    const Eigen::Vector3f origin = f.pose.translation().cast<float>();
    RayHit hit;
    ASSERT_TRUE(f.scene.intersect(origin, (f.pose.rotation() * direction_cam).cast<float>(),
                                  &hit));
    const Eigen::Vector3d point_world =
        f.pose.translation() + hit.distance * (f.pose.rotation() * direction_cam);
    const double radiance = f.scene.radiance(hit);
    Eigen::Vector2d uv;
    if (!f.camera.project(f.pose.inverse() * point_world, uv)) continue;
    if (uv.x() < 1 || uv.y() < 1 || uv.x() > 94 || uv.y() > 94) continue;
    const int u0 = static_cast<int>(std::floor(uv.x()));
    const int v0 = static_cast<int>(std::floor(uv.y()));
    double e_min = 1e9;
    double e_max = -1e9;
    bool complete = true;
    for (int dv = 0; dv <= 1; ++dv) {
      for (int du = 0; du <= 1; ++du) {
        const double vignette = renderer.vignette()(u0 + du, v0 + dv);
        for (const double sv : {-0.25, 0.25}) {
          for (const double su : {-0.25, 0.25}) {
            const float b = radianceThrough(f, Eigen::Vector2d(u0 + du + su, v0 + dv + sv));
            complete = complete && b >= 0.f;
            e_min = std::min(e_min, scale * vignette * b);
            e_max = std::max(e_max, scale * vignette * b);
          }
        }
      }
    }
    const double vignette_at_uv = model.vignette(uv.x(), uv.y(), 96, 96, f.camera.params()[2],
                                                 f.camera.params()[3]);
    const double expected = model.response(scale * vignette_at_uv * radiance);
    const double bound_lo = std::min(model.response(e_min), expected);
    const double bound_hi = std::max(model.response(e_max), expected);
    if (!complete || bound_hi - bound_lo > 3.0) continue;  // not a smooth spot
    const double fu = uv.x() - u0;
    const double fv = uv.y() - v0;
    const double rendered = (1 - fv) * ((1 - fu) * image(u0, v0) + fu * image(u0 + 1, v0)) +
                            fv * ((1 - fu) * image(u0, v0 + 1) + fu * image(u0 + 1, v0 + 1));
    EXPECT_NEAR(rendered, expected, bound_hi - bound_lo + 0.5)
        << "point " << point_world.transpose() << " at uv " << uv.transpose();
    ++tested;
    if (direction_cam.z() < 0) ++behind_camera;
  }
  EXPECT_GE(tested, 40);
  // The 185° UCM camera sees points behind its image plane too; some must be among them.
  EXPECT_GE(behind_camera, 1);
}

TEST(RendererTest, OutputIsIndependentOfTheThreadCount) {
  const RenderFixture f;
  const ImageU8 one = makeRenderer(f, true, 1).render({f.pose}, 10.0, 3);
  const ImageU8 three = makeRenderer(f, true, 3).render({f.pose}, 10.0, 3);
  EXPECT_TRUE(one == three);
}

// Same seed, same bytes; another seed changes the noise only: the noise-free radiance is
// the same, and the pixel differences have zero mean. Per-pixel noise is ~1.5 grey levels
// (σ_E ≈ 1.8 at E ≈ 60 through G' ≈ 0.8), so most pixels differ between seeds.
TEST(RendererTest, SeedsChangeNoiseOnly) {
  const RenderFixture f;
  const Renderer a = makeRenderer(f, true, 2, 1);
  const Renderer b = makeRenderer(f, true, 2, 2);
  const ImageF radiance = a.renderRadiance({f.pose});
  EXPECT_TRUE(radiance == b.renderRadiance({f.pose}));
  const ImageU8 a1 = a.toPixels(radiance, 10.0, 0);
  EXPECT_TRUE(a1 == a.toPixels(radiance, 10.0, 0));
  const ImageU8 b1 = b.toPixels(radiance, 10.0, 0);
  const ImageU8 a_next_frame = a.toPixels(radiance, 10.0, 1);
  int differing = 0;
  int valid = 0;
  double sum = 0;
  for (size_t i = 0; i < a1.size(); ++i) {
    if (a.vignette().data()[i] <= 0.f) continue;
    ++valid;
    differing += a1.data()[i] != b1.data()[i];
    sum += static_cast<double>(a1.data()[i]) - b1.data()[i];
  }
  EXPECT_GT(differing, valid / 2);
  // Mean of ~9000 differences with σ ≈ 2.1: standard error 0.02; 0.15 is > 5σ.
  EXPECT_NEAR(sum / valid, 0.0, 0.15);
  EXPECT_FALSE(a1 == a_next_frame);  // noise is fresh in every frame
}

TEST(RendererTest, MotionBlurAveragesThePosesOverTheExposure) {
  const RenderFixture f;
  const Renderer renderer = makeRenderer(f, false);
  const SE3d moved(f.pose.rotation(), f.pose.translation() + Eigen::Vector3d(0.05, 0, 0));
  // All samples at one pose: the same as the unblurred image.
  EXPECT_TRUE(renderer.renderRadiance({f.pose, f.pose}) == renderer.renderRadiance({f.pose}));
  // Two poses: half of each pixel's samples see the moved scene, so the image changes.
  const ImageF blurred = renderer.renderRadiance({f.pose, moved});
  const ImageF sharp = renderer.renderRadiance({f.pose});
  EXPECT_FALSE(blurred == sharp);
}

TEST(RendererTest, VignetteIsTheRadialFalloffInsideTheImage) {
  const RenderFixture f;
  const Renderer renderer = makeRenderer(f, false);
  const PhotometricModel& model = renderer.photometric();
  // UCM with ξ < 1 unprojects every pixel, so V follows the formula everywhere.
  EXPECT_NEAR(renderer.vignette()(0, 0), model.vignette(0, 0, 96, 96, 47.5, 47.5), 1e-6);
  EXPECT_NEAR(renderer.vignette()(48, 47), model.vignette(48, 47, 96, 96, 47.5, 47.5), 1e-6);
  EXPECT_LT(renderer.vignette()(0, 0), renderer.vignette()(48, 47));
  // V = 1 + v₁r² + v₂r⁴ with r = ‖x − c‖ / half diagonal = 49.5√2 / 50√2 at the corner.
  const double r2 = std::pow(49.5 / 50.0, 2);
  EXPECT_NEAR(model.vignette(0, 0, 100, 100, 49.5, 49.5),
              1 + model.vignette_r2 * r2 + model.vignette_r4 * r2 * r2, 1e-12);
}

TEST(RendererTest, ResponseAndInverseResponseAreInverses) {
  const PhotometricModel model;
  for (int k = 0; k <= 255; k += 15) {
    EXPECT_NEAR(model.response(model.inverseResponse(k)), k, 1e-9);
  }
  const InverseResponse table = model.inverseResponseTable();
  EXPECT_DOUBLE_EQ(table[0], 0.0);
  EXPECT_DOUBLE_EQ(table[255], 255.0);
  for (int k = 1; k < 256; ++k) EXPECT_GT(table[k], table[k - 1]);
}

TEST(RendererTest, AutoExposureMovesTowardTheTargetSmoothly) {
  const AutoExposure exposure;
  // Too dark: longer exposure, by (target/mean)^rate; never beyond the limits.
  EXPECT_NEAR(exposure.next(10.0, exposure.target_mean / 2),
              10.0 * std::pow(2.0, exposure.rate), 1e-12);
  EXPECT_LT(exposure.next(10.0, 200.0), 10.0);
  EXPECT_EQ(exposure.next(exposure.max_ms, 1.0), exposure.max_ms);
}

}  // namespace
}  // namespace omnidso::synth
