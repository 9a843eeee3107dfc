#pragma once
// Shared by the coarse tracker's tests: the pose error, the reference's points on a rendered
// room, and that room seen from its central pose as a tracking reference.
#include <cmath>
#include <memory>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/frontend/coarse_tracker.hpp>
#include <omnidso/frontend/pixel_selector.hpp>
#include <vector>

#include "support/rendered_scene.hpp"

namespace omnidso {
namespace test {

struct PoseError {
  double translation_m, rotation_deg;
};

inline PoseError poseError(const SE3d& a, const SE3d& b) {
  const SE3d d = a.inverse() * b;
  return {d.translation().norm(), so3Log(d.rotation()).norm() * 180.0 / M_PI};
}

// The reference's points: DSO's selection on the reference image inside `usable`, with the
// scene's true inverse distances.
inline std::vector<TrackingReferencePoint> referencePoints(const Camera& camera,
                                                    const RenderedScene& scene,
                                                    const SE3d& T_world_ref,
                                                    const ImagePyramid& ref, const Mask& usable) {
  PixelSelectorOptions selection;
  selection.desired_points = 1500;
  std::vector<TrackingReferencePoint> points;
  for (const SelectedPixel& p : selectPixels(ref, usable, selection)) {
    Eigen::Vector3d bearing;
    if (!camera.unproject(p.pixel.cast<double>(), bearing)) continue;
    const auto rho = scene.distance(T_world_ref, bearing);
    if (rho) points.push_back({p.pixel.cast<double>(), 1.0 / *rho});
  }
  return points;
}

// The rendered room (seed 11) from its central pose as a tracking reference: the pyramid and
// DSO's selection on it with the scene's inverse distances.
struct RenderedReference {
  explicit RenderedReference(const Camera& c)
      : camera(c),
        scene(c, 11),
        T_world_ref(scene.centralPose()),
        pyramid(scene.renderPyramid(T_world_ref)),
        points(referencePoints(camera, scene, T_world_ref, *pyramid, validityMask(camera))) {}
  Camera camera;
  RenderedScene scene;
  SE3d T_world_ref;
  std::shared_ptr<const ImagePyramid> pyramid;
  std::vector<TrackingReferencePoint> points;
};

}  // namespace test
}  // namespace omnidso
