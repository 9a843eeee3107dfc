#pragma once
// The unit bearings of a camera's sub-pixel samples, computed once: they are constant in
// the camera frame, so rendering a frame only rotates them by the pose (renderer.hpp).
// Works with any camera that has `bool unproject(const Eigen::Vector2d&, Eigen::Vector3d&)`
// (the model templates of omnidso::cameras and the runtime omnidso::Camera).
//
// Samples are stratified and deterministic: n × n per pixel at offsets (i + ½)/n − ½ from
// the pixel centre (pixel centres at integer (u, v), docs/architecture.md).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include <omnidso/core/image.hpp>

namespace omnidso::synth {

struct BearingTable {
  int width = 0;
  int height = 0;
  int samples_per_axis = 2;
  // bearings[(v·width + u)·n² + j]: sample j of pixel (u, v); zero where the model has no
  // ray (outside the image circle or its domain).
  std::vector<Eigen::Vector3f> bearings;
  // Optical centre for the vignette (the principal point).
  double cx = 0;
  double cy = 0;

  int samplesPerPixel() const { return samples_per_axis * samples_per_axis; }
  double sampleOffset(int i) const { return (i + 0.5) / samples_per_axis - 0.5; }
};

template <typename CameraT>
BearingTable makeBearingTable(const CameraT& camera, int width, int height,
                              int samples_per_axis, double cx, double cy) {
  BearingTable table;
  table.width = width;
  table.height = height;
  table.samples_per_axis = samples_per_axis;
  table.cx = cx;
  table.cy = cy;
  const int per_pixel = samples_per_axis * samples_per_axis;
  table.bearings.assign(static_cast<size_t>(width) * height * per_pixel, Eigen::Vector3f::Zero());
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      for (int j = 0; j < per_pixel; ++j) {
        const Eigen::Vector2d uv(u + table.sampleOffset(j % samples_per_axis),
                                 v + table.sampleOffset(j / samples_per_axis));
        Eigen::Vector3d bearing;
        if (camera.unproject(uv, bearing) && bearing.allFinite()) {
          table.bearings[(static_cast<size_t>(v) * width + u) * per_pixel + j] =
              bearing.normalized().cast<float>();
        }
      }
    }
  }
  return table;
}

}  // namespace omnidso::synth
