#include "omnidso/core/pyramid.hpp"

#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include "omnidso/core/error.hpp"

namespace omnidso {

struct ImagePyramid::EncodingSlopes {
  std::shared_ptr<const CameraEncoding> encoding;
  std::vector<ImageF> levels;
  std::unique_ptr<std::once_flag[]> once;
};

ImagePyramid::ImagePyramid(ImageF level0, int num_levels,
                           std::shared_ptr<const std::vector<Mask>> content,
                           std::shared_ptr<const CameraEncoding> encoding)
    : content_(std::move(content)) {
  if (num_levels < 1) {
    throw Error("ImagePyramid: number of levels must be at least 1, got " +
                std::to_string(num_levels));
  }
  // Each level halves (floor) the size of the previous one.
  int coarsest_width = level0.width();
  int coarsest_height = level0.height();
  for (int l = 1; l < num_levels; ++l) {
    coarsest_width /= 2;
    coarsest_height /= 2;
  }
  if (coarsest_width < kMinCoarsestSize || coarsest_height < kMinCoarsestSize) {
    throw Error("ImagePyramid: a " + std::to_string(level0.width()) + "x" +
                std::to_string(level0.height()) + " image is too small for " +
                std::to_string(num_levels) + " levels (the coarsest level needs at least " +
                std::to_string(kMinCoarsestSize) + "x" + std::to_string(kMinCoarsestSize) +
                " pixels)");
  }
  levels_.reserve(num_levels);
  gradients_.reserve(num_levels);
  levels_.push_back(std::move(level0));
  for (int l = 1; l < num_levels; ++l) levels_.push_back(downsample2x2(levels_.back()));
  for (const ImageF& level : levels_) gradients_.push_back(computeGradients(level));
  if (encoding && !encoding->linear()) {
    for (int l = 0; l < num_levels; ++l)
      encoding->checkLevel(levels_[l].width(), levels_[l].height(), l);
    encoding_slopes_ = std::make_shared<EncodingSlopes>();
    encoding_slopes_->encoding = std::move(encoding);
    encoding_slopes_->levels.resize(static_cast<size_t>(num_levels));
    encoding_slopes_->once = std::make_unique<std::once_flag[]>(static_cast<size_t>(num_levels));
  }
  if (content_) {
    if (static_cast<int>(content_->size()) < num_levels)
      throw Error("ImagePyramid: " + std::to_string(content_->size()) +
                  " content masks for " + std::to_string(num_levels) + " levels");
    for (int l = 0; l < num_levels; ++l)
      if ((*content_)[l].width() != levels_[l].width() ||
          (*content_)[l].height() != levels_[l].height())
        throw Error("ImagePyramid: the content mask of level " + std::to_string(l) + " is " +
                    std::to_string((*content_)[l].width()) + "x" +
                    std::to_string((*content_)[l].height()) + ", the level " +
                    std::to_string(levels_[l].width()) + "x" +
                    std::to_string(levels_[l].height()));
  }
}

const Mask* ImagePyramid::content(int index) const {
  if (!content_) return nullptr;
  level(index);  // range check
  return &(*content_)[index];
}

const ImageF* ImagePyramid::encodingSlope(int index) const {
  level(index);  // range check
  if (!encoding_slopes_) return nullptr;
  EncodingSlopes& e = *encoding_slopes_;
  const size_t l = static_cast<size_t>(index);
  std::call_once(e.once[l], [&] { e.levels[l] = e.encoding->slope(levels_[l], index); });
  return &e.levels[l];
}

const ImageF& ImagePyramid::level(int index) const {
  if (index < 0 || index >= numLevels()) {
    throw Error("ImagePyramid: level " + std::to_string(index) + " out of range [0, " +
                std::to_string(numLevels()) + ")");
  }
  return levels_[index];
}

const ImageGradients& ImagePyramid::gradients(int index) const {
  if (index < 0 || index >= numLevels()) {
    throw Error("ImagePyramid: level " + std::to_string(index) + " out of range [0, " +
                std::to_string(numLevels()) + ")");
  }
  return gradients_[index];
}

int pyramidLevelsForImage(int width, int height, int min_coarsest_pixels, int max_levels) {
  int levels = 1;
  long w = width, h = height;
  while (levels < max_levels && w * h > min_coarsest_pixels &&
         w / 2 >= ImagePyramid::kMinCoarsestSize && h / 2 >= ImagePyramid::kMinCoarsestSize) {
    w /= 2;
    h /= 2;
    ++levels;
  }
  return levels;
}

}  // namespace omnidso
