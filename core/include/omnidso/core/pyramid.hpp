#pragma once
// An image pyramid for coarse-to-fine tracking (design: 5 levels). Level 0 is the input,
// each further level the 2×2 mean of the previous one (image_ops.hpp); the gradients of
// every level are computed once here because tracking and pixel selection read them many
// times.

#include <vector>

#include "omnidso/core/image.hpp"
#include "omnidso/core/image_ops.hpp"

namespace omnidso {

class ImagePyramid {
 public:
  static constexpr int kDefaultNumLevels = 5;
  // The coarsest level must be at least this wide and high: central differences and a
  // bilinear cell need two pixels along each axis.
  static constexpr int kMinCoarsestSize = 2;

  // Throws omnidso::Error if num_levels < 1 or the coarsest level would be smaller than
  // kMinCoarsestSize along either axis.
  explicit ImagePyramid(ImageF level0, int num_levels = kDefaultNumLevels);

  int numLevels() const { return static_cast<int>(levels_.size()); }
  const ImageF& level(int index) const;
  const ImageGradients& gradients(int index) const;

 private:
  std::vector<ImageF> levels_;
  std::vector<ImageGradients> gradients_;
};

}  // namespace omnidso
