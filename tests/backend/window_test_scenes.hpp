#pragma once
// Windows built from rendered scenes for the backend tests (sliding_window_test.cc,
// window_solver_test.cc): keyframes along a motion with their rendered pyramids, points at
// the strongest gradients with their true inverse distances, perturbations, and the
// bit-for-bit comparison of two windows.

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <omnidso/backend/sliding_window.hpp>
#include <omnidso/synth/synthetic_sequence.hpp>
#include <utility>
#include <vector>

#include "support/rendered_scene.hpp"

namespace omnidso::test {

// A lens-like blur of 1 px: see RenderedScene::render.
inline constexpr double kBlurSigmaPx = 1.0;

struct WindowScene {
  test::RenderedScene scene;
  std::vector<SE3d> poses;  // ground truth T_world_cam
  std::vector<std::shared_ptr<const ImagePyramid>> images;

  // Keyframe k at start · exp(motion(k)), motion giving [translation m; rotation deg].
  template <typename Motion>
  WindowScene(const Camera& camera, int num_keyframes, Motion motion) : scene(camera, 5) {
    const SE3d start = scene.centralPose();
    for (int k = 0; k < num_keyframes; ++k) {
      const auto [rho, phi_deg] = motion(k);
      poses.push_back(moveInCamera(start, rho, phi_deg));
      images.push_back(scene.renderPyramid(poses.back(), 5, kBlurSigmaPx));
    }
  }
};

// A short forward-sideways sweep turning by 4° per keyframe (as hand-held odometry sees).
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> sweep(int k) {
  return {{0.06 * k, 0.01 * k, 0.04 * k}, {0.5 * k, 4.0 * k, 0.0}};
}

// The fisheye camera of the window tests (UCM, 185°, 320 × 320) and its sweep of
// `num_keyframes` keyframes, rendered once per test process and count.
inline const Camera& sweepCamera() {
  static const Camera camera = synth::syntheticCamera("ucm", 185.0, 320, 320);
  return camera;
}

inline const WindowScene& sweepScene(int num_keyframes) {
  static std::map<int, std::unique_ptr<const WindowScene>> scenes;
  std::unique_ptr<const WindowScene>& scene = scenes[num_keyframes];
  if (!scene) scene = std::make_unique<const WindowScene>(sweepCamera(), num_keyframes, sweep);
  return *scene;
}

// The strongest-gradient valid pixel of every cell × cell block (a simple stand-in for the
// frontend's pixel selector, which the backend does not depend on).
inline std::vector<Eigen::Vector2i> gradientPixels(const ImagePyramid& image, const Mask& mask,
                                                   int cell) {
  const ImageGradients& g = image.gradients(0);
  std::vector<Eigen::Vector2i> out;
  for (int v0 = 4; v0 + cell < g.dx.height() - 4; v0 += cell)
    for (int u0 = 4; u0 + cell < g.dx.width() - 4; u0 += cell) {
      float best = 20.f;  // intensity units per pixel: textured, not flat
      Eigen::Vector2i arg(-1, -1);
      for (int v = v0; v < v0 + cell; ++v)
        for (int u = u0; u < u0 + cell; ++u) {
          const float m = std::hypot(g.dx(u, v), g.dy(u, v));
          if (mask(u, v) && m > best) {
            best = m;
            arg = {u, v};
          }
        }
      if (arg.x() >= 0) out.push_back(arg);
    }
  return out;
}

// Window options for recovering a perturbed state. Iterations per level: DSO's 6 suit the
// odometry, whose estimates arrive nearly right; recovering 2 cm / 1° from scratch takes more.
inline WindowOptions recoveryOptions(int num_keyframes, bool optimize_intrinsics) {
  WindowOptions options;
  options.max_keyframes = num_keyframes;
  options.optimize_intrinsics = optimize_intrinsics;
  // Recovering perturbed intrinsics needs them free: the prior would hold them at the start.
  options.intrinsics_prior_weight = 0.0;
  options.max_iterations = 100;
  return options;
}

// The window at ground truth: the scene's keyframes, and one point at the strongest-gradient
// pixel of every cell × cell block of each keyframe with its true inverse distance
// (returned in true_inverse_distance by point id).
inline std::unique_ptr<SlidingWindow> groundTruthWindow(
    const Camera& camera, const WindowScene& ws, const WindowOptions& options, int cell,
    std::map<int, double>* true_inverse_distance) {
  auto window = std::make_unique<SlidingWindow>(camera.modelName(), camera.params(), options);
  const int num_keyframes = static_cast<int>(ws.poses.size());
  for (int k = 0; k < num_keyframes; ++k)
    window->addKeyframe(k, 0.1 * k, 1.0, ws.poses[k], Eigen::Vector2d::Zero(), ws.images[k]);
  const Mask mask = validityMask(camera);
  for (int k = 0; k < num_keyframes; ++k) {
    for (const Eigen::Vector2i& pixel : gradientPixels(*ws.images[k], mask, cell)) {
      Eigen::Vector3d bearing;
      if (!camera.unproject(pixel.cast<double>(), bearing)) continue;
      const auto rho = ws.scene.distance(ws.poses[k], bearing);
      if (!rho) continue;
      const int id = window->addPoint(k, pixel.cast<double>(), 1.0 / *rho);
      if (id >= 0) (*true_inverse_distance)[id] = 1.0 / *rho;
    }
  }
  return window;
}

// The ground-truth window with every inverse distance off by −10, 0 or +10 % and the newest
// keyframe moved by 1 cm and 0.5°: the start of the solver comparisons.
inline std::unique_ptr<SlidingWindow> perturbedWindow(const Camera& camera, const WindowScene& ws,
                                                      const WindowOptions& options,
                                                      int num_keyframes) {
  std::map<int, double> true_d;
  auto window = groundTruthWindow(camera, ws, options, 24, &true_d);
  for (const auto& [id, d] : true_d)
    window->mutablePoint(id).inverse_distance = d * (1.0 + 0.1 * (id % 3 - 1));
  WindowKeyframe& kf = window->mutableKeyframe(num_keyframes - 1);
  moveInCamera(kf.T_world_cam(), Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0.5, 0, 0))
      .toParameters(kf.pose.data());
  return window;
}

// Keyframes (pose and affine), intrinsics and points equal bit for bit.
inline void expectSameStateBitForBit(const SlidingWindow& a, const SlidingWindow& b) {
  ASSERT_EQ(a.keyframeIds(), b.keyframeIds());
  for (int id : a.keyframeIds()) {
    EXPECT_EQ(a.keyframe(id).pose, b.keyframe(id).pose) << "keyframe " << id;
    EXPECT_EQ(a.keyframe(id).affine, b.keyframe(id).affine) << "keyframe " << id;
  }
  EXPECT_EQ(a.intrinsics(), b.intrinsics());
  ASSERT_EQ(a.numPoints(), b.numPoints());
  auto it = b.points().begin();
  for (const auto& [id, point] : a.points())
    EXPECT_EQ(point->inverse_distance, (it++)->second->inverse_distance) << "point " << id;
}

}  // namespace omnidso::test
