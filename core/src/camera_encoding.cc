#include "omnidso/core/camera_encoding.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "omnidso/core/error.hpp"
#include "omnidso/core/image_ops.hpp"

namespace omnidso {

CameraEncoding::CameraEncoding(std::vector<float> response_slope, const ImageF& vignette)
    : response_slope_(std::move(response_slope)) {
  if (!response_slope_.empty() && response_slope_.size() != 256)
    throw Error("CameraEncoding: the response's slope needs 256 values, got " +
                std::to_string(response_slope_.size()));
  if (vignette.empty()) return;
  vignette_levels_.push_back(vignette);
  while (vignette_levels_.back().width() / 2 >= 2 && vignette_levels_.back().height() / 2 >= 2)
    vignette_levels_.push_back(downsample2x2(vignette_levels_.back()));
}

void CameraEncoding::checkLevel(int width, int height, int level) const {
  if (vignette_levels_.empty()) return;
  if (level < 0 || level >= static_cast<int>(vignette_levels_.size()))
    throw Error("CameraEncoding: the vignette has no pyramid level " + std::to_string(level));
  const ImageF& vignette = vignette_levels_[static_cast<size_t>(level)];
  if (vignette.width() != width || vignette.height() != height)
    throw Error("CameraEncoding: the vignette of level " + std::to_string(level) + " is " +
                std::to_string(vignette.width()) + "x" + std::to_string(vignette.height()) +
                ", the image " + std::to_string(width) + "x" + std::to_string(height));
}

ImageF CameraEncoding::slope(const ImageF& intensity, int level) const {
  checkLevel(intensity.width(), intensity.height(), level);
  const ImageF* vignette =
      vignette_levels_.empty() ? nullptr : &vignette_levels_[static_cast<size_t>(level)];
  ImageF out(intensity.width(), intensity.height(), 1.f);
  const float* e = intensity.data();
  const float* v = vignette ? vignette->data() : nullptr;
  float* s = out.data();
  for (size_t i = 0; i < out.size(); ++i) {
    const float attenuation = v ? v[i] : 1.f;
    const float raw = attenuation * e[i];  // V E, the response's argument
    const float g = response_slope_.empty()
                        ? 1.f
                        : response_slope_[static_cast<size_t>(
                              std::clamp(static_cast<int>(raw + 0.5f), 0, 255))];
    s[i] = g * attenuation;
  }
  return out;
}

}  // namespace omnidso
