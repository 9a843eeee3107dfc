// Ray casting against the room scene and its textures.
#include <omnidso/synth/scene.hpp>

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <omnidso/core/error.hpp>
#include <omnidso/synth/random.hpp>

#include "synth_test_util.hpp"

namespace omnidso::synth {
namespace {

Scene testScene() {
  RoomSceneConfig config;
  config.texel_size = 0.02;
  return makeRoomScene(config, 11);
}

// Float arithmetic on distances of a few metres: relative error ~1e-7 · few ops, so 1e-4 m.
constexpr float kDistanceTolerance = 1e-4f;

TEST(SceneTest, RayFromTheFreeSpaceHitsTheFarWall) {
  const Scene scene = testScene();
  const Eigen::Vector3f origin(4.f, 3.f, 1.45f);
  RayHit hit;
  ASSERT_TRUE(scene.intersect(origin, Eigen::Vector3f::UnitX(), &hit));
  EXPECT_EQ(hit.box, 0);   // the room
  EXPECT_EQ(hit.face, 1);  // its +x wall
  EXPECT_NEAR(hit.distance, 4.f, kDistanceTolerance);
  // x faces are parameterised by (y, z) from the room's corner.
  EXPECT_NEAR(hit.s, 3.f, kDistanceTolerance);
  EXPECT_NEAR(hit.t, 1.45f, kDistanceTolerance);
}

TEST(SceneTest, RayHitsTheTableTopBeforeTheFloor) {
  const Scene scene = testScene();
  const Eigen::Vector3f origin(4.f, 3.f, 1.45f);
  const Eigen::Vector3f target(7.f, 3.f, 0.8f);  // centre of the table's top face
  RayHit hit;
  ASSERT_TRUE(scene.intersect(origin, (target - origin).normalized(), &hit));
  EXPECT_EQ(hit.box, 2);
  EXPECT_EQ(hit.face, 5);  // +z
  EXPECT_NEAR(hit.distance, (target - origin).norm(), kDistanceTolerance);
}

TEST(SceneTest, RayHitsTheTurnedCrateOnItsRotatedFace) {
  const Scene scene = testScene();
  // The crate: centre (4, 5.3, 0.3), half size 0.35, yaw 0.6. Along world +y through its
  // centre the ray meets the face where the box-frame coordinate of larger slope reaches
  // the half size: after 0.35 / max(|sin 0.6|, |cos 0.6|) before the centre.
  const Eigen::Vector3f origin(4.f, 3.f, 0.3f);
  RayHit hit;
  ASSERT_TRUE(scene.intersect(origin, Eigen::Vector3f::UnitY(), &hit));
  EXPECT_EQ(hit.box, 4);
  const float expected = 2.3f - 0.35f / std::max(std::abs(std::sin(0.6f)), std::cos(0.6f));
  EXPECT_NEAR(hit.distance, expected, kDistanceTolerance);
}

TEST(SceneTest, EveryRayFromTheFreeSpaceHitsASurfaceInsideTheRoom) {
  const Scene scene = testScene();
  const AlignedBox room = scene.roomBounds();
  SeededRandom random(3);
  for (int i = 0; i < 2000; ++i) {
    const AlignedBox& free = scene.freeSpace();
    const Eigen::Vector3d origin(random.uniform(free.min.x(), free.max.x()),
                                 random.uniform(free.min.y(), free.max.y()),
                                 random.uniform(free.min.z(), free.max.z()));
    const Eigen::Vector3d direction =
        Eigen::Vector3d(random.gaussian(), random.gaussian(), random.gaussian()).normalized();
    RayHit hit;
    ASSERT_TRUE(scene.intersect(origin.cast<float>(), direction.cast<float>(), &hit));
    const Eigen::Vector3d point = origin + hit.distance * direction;
    EXPECT_TRUE((point.array() >= room.min.array() - 1e-3).all() &&
                (point.array() <= room.max.array() + 1e-3).all());
    const float radiance = scene.radiance(hit);
    EXPECT_GE(radiance, kMinRadiance);
    EXPECT_LE(radiance, 1.f);
  }
}

TEST(SceneTest, NoObjectReachesIntoTheFreeSpace) {
  const Scene scene = testScene();
  const AlignedBox& free = scene.freeSpace();
  for (size_t b = 1; b < scene.boxes().size(); ++b) {
    const SceneBox& box = scene.boxes()[b];
    // Bounding box of the turned box: half extents |cos|·hx + |sin|·hy (and swapped).
    const double c = std::abs(std::cos(box.yaw));
    const double s = std::abs(std::sin(box.yaw));
    const Eigen::Vector3d half(c * box.half_size.x() + s * box.half_size.y(),
                               s * box.half_size.x() + c * box.half_size.y(), box.half_size.z());
    const Eigen::Vector3d lo = box.centre.cast<double>() - half;
    const Eigen::Vector3d hi = box.centre.cast<double>() + half;
    const bool overlaps = (lo.array() < free.max.array()).all() &&
                          (hi.array() > free.min.array()).all();
    EXPECT_FALSE(overlaps) << "object " << b;
  }
}

TEST(SceneTest, TexturesAreReproducibleBySeed) {
  TextureRecipe recipe;
  const ImageF a = makeProceduralRadiance(1.0, 0.5, 0.01, recipe, 42);
  const ImageF b = makeProceduralRadiance(1.0, 0.5, 0.01, recipe, 42);
  const ImageF c = makeProceduralRadiance(1.0, 0.5, 0.01, recipe, 43);
  EXPECT_EQ(a.width(), 100);
  EXPECT_EQ(a.height(), 50);
  EXPECT_TRUE(a == b);
  EXPECT_FALSE(a == c);
}

TEST(SceneTest, TextureSamplesTexelCentresExactlyAndInterpolatesBetween) {
  ImageF radiance(3, 2);
  for (int v = 0; v < 2; ++v) {
    for (int u = 0; u < 3; ++u) radiance(u, v) = 0.1f * static_cast<float>(u + 3 * v + 1);
  }
  const Texture texture(radiance, 0.5);
  // Texel (u, v) has its centre at ((u + ½)·0.5, (v + ½)·0.5) metres.
  EXPECT_FLOAT_EQ(texture.sample(0.25f, 0.25f), 0.1f);
  EXPECT_FLOAT_EQ(texture.sample(1.25f, 0.75f), 0.6f);
  // Halfway between texels (0,0) and (1,0): the mean (bilinear).
  EXPECT_NEAR(texture.sample(0.5f, 0.25f), 0.15f, 1e-6f);
  // Beyond the last centre: clamped to the edge texel.
  EXPECT_FLOAT_EQ(texture.sample(1.5f, 1.0f), 0.6f);
}

TEST(SceneTest, ImageFilesBecomePosterTextures) {
  test::TempDir tmp("poster");
  const std::string path = (tmp.path() / "poster.png").string();
  // Left half black, right half 204 (= 0.8 · 255).
  cv::Mat poster(10, 20, CV_8UC1, cv::Scalar(0));
  poster.colRange(10, 20).setTo(204);
  cv::imwrite(path, poster);
  ImageF radiance(100, 100, 0.5f);
  pasteImagePoster(radiance, 0.01, path, 0.2, 0.3, 0.4, 0.2);  // 40 × 20 texels at (20, 30)
  EXPECT_FLOAT_EQ(radiance(19, 35), 0.5f);          // outside
  EXPECT_FLOAT_EQ(radiance(25, 35), kMinRadiance);  // black → the darkest radiance
  EXPECT_FLOAT_EQ(radiance(55, 45), 0.8f);
  EXPECT_FLOAT_EQ(radiance(60, 45), 0.5f);          // right of the poster
  EXPECT_THROW(pasteImagePoster(radiance, 0.01, path + ".absent", 0, 0, 1, 1), Error);

  RoomSceneConfig config;
  config.texel_size = 0.02;
  config.poster_images = {path};
  const Scene with_poster = makeRoomScene(config, 11);
  // The first poster goes on the −x wall, 1 m along y and 1 m up: its right half is 0.8.
  RayHit hit;
  ASSERT_TRUE(with_poster.intersect(Eigen::Vector3f(4.f, 1.9f, 1.45f), -Eigen::Vector3f::UnitX(),
                                    &hit));
  EXPECT_EQ(hit.face, 0);
  EXPECT_FLOAT_EQ(with_poster.radiance(hit), 0.8f);
}

}  // namespace
}  // namespace omnidso::synth
