#pragma once
// A dense row-major image. Pixel (u, v) = (column, row); the centre of the top-left pixel
// is (0, 0) (docs/architecture.md). Intensities in the odometry are float irradiance
// after photometric correction; masks are uint8 (0 = invalid, non-zero = valid).

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace omnidso {

template <typename T>
class Image {
 public:
  using Pixel = T;

  Image() = default;
  Image(int width, int height, T fill = T())
      : width_(width), height_(height), data_(static_cast<std::size_t>(width) * height, fill) {
    assert(width >= 0 && height >= 0);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return data_.empty(); }
  std::size_t size() const { return data_.size(); }

  // (column u, row v)
  T& operator()(int u, int v) {
    assert(contains(u, v));
    return data_[static_cast<std::size_t>(v) * width_ + u];
  }
  const T& operator()(int u, int v) const {
    assert(contains(u, v));
    return data_[static_cast<std::size_t>(v) * width_ + u];
  }
  bool contains(int u, int v) const { return u >= 0 && v >= 0 && u < width_ && v < height_; }

  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }
  T* row(int v) { return data_.data() + static_cast<std::size_t>(v) * width_; }
  const T* row(int v) const { return data_.data() + static_cast<std::size_t>(v) * width_; }

  bool operator==(const Image& o) const {
    return width_ == o.width_ && height_ == o.height_ && data_ == o.data_;
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> data_;
};

using ImageF = Image<float>;
using ImageU8 = Image<std::uint8_t>;
using ImageU16 = Image<std::uint16_t>;
using Mask = Image<std::uint8_t>;

}  // namespace omnidso
