// Two projections inlined into one function each keep their own pixel, for every model.
//
// GCC 12.2 at -O3 (Release) miscompiled this: with two calls of PinholeCamera::project
// inlined into one function, the second pixel kept the first one's v (the row of an Eigen
// comma initialiser `uv << u, v` was dropped; -O2, clang and -fno-ipa-modref were right).
// The top-level CMakeLists.txt builds with -fno-ipa-modref on GCC 11–12 for this reason; this
// test fails without it (checked against the session-44 build) and guards other compilers.

#include "cameras/camera_model_test_utils.hpp"

#include <gtest/gtest.h>

#include <array>
#include <stdexcept>

namespace omnidso {
namespace {

using test::TestCamera;

template <typename Model>
class TwoProjectionsTest : public ::testing::Test {
 protected:
  std::vector<TestCamera<Model>> cameras_ = test::realisticCameras<Model>();
};

using ModelTypes = test::TupleToTypes<AllCameraModels>::type;
TYPED_TEST_SUITE(TwoProjectionsTest, ModelTypes);

// noinline: the two inlined projections must share this one function, as in the failure
// (its points built from scalars inside, one output reused).
template <typename Model>
__attribute__((noinline)) std::array<Eigen::Vector2d, 2> projectTwo(const Model& camera,
                                                                    double ax, double ay,
                                                                    double az, double bx,
                                                                    double by, double bz) {
  std::array<Eigen::Vector2d, 2> out;
  Eigen::Vector2d uv;
  if (!camera.project(Eigen::Vector3d(ax, ay, az), uv)) throw std::runtime_error("a");
  out[0].x() = uv.x();
  out[0].y() = uv.y();
  if (!camera.project(Eigen::Vector3d(bx, by, bz), uv)) throw std::runtime_error("b");
  out[1].x() = uv.x();
  out[1].y() = uv.y();
  return out;
}

template <typename Model>
__attribute__((noinline)) Eigen::Vector2d projectOne(const Model& camera,
                                                     const Eigen::Vector3d& p) {
  Eigen::Vector2d uv;
  return camera.project(p, uv) ? uv : Eigen::Vector2d::Constant(-1.0);
}

// The same arithmetic in both paths: the pixels agree to rounding (1e-9 px is a million times
// the rounding of a ~1000 px coordinate and far below the rows' difference of pixels).
TYPED_TEST(TwoProjectionsTest, EachKeepsItsOwnPixel) {
  for (const auto& tc : this->cameras_) {
    SCOPED_TRACE(tc.label);
    const std::vector<Eigen::Vector3d> points = test::randomValidPoints(tc, 200, 11);
    for (size_t i = 0; i + 1 < points.size(); i += 2) {
      const std::array<Eigen::Vector2d, 2> both = projectTwo(
          tc.camera, points[i].x(), points[i].y(), points[i].z(), points[i + 1].x(),
          points[i + 1].y(), points[i + 1].z());
      EXPECT_LT((both[0] - projectOne(tc.camera, points[i])).norm(), 1e-9);
      EXPECT_LT((both[1] - projectOne(tc.camera, points[i + 1])).norm(), 1e-9);
    }
  }
}

}  // namespace
}  // namespace omnidso
