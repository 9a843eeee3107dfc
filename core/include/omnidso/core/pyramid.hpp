#pragma once
// An image pyramid for coarse-to-fine tracking (design: 5 levels). Level 0 is the input,
// each further level the 2×2 mean of the previous one (image_ops.hpp); the gradients of
// every level are computed once here because tracking and pixel selection read them many
// times.

#include <memory>
#include <vector>

#include "omnidso/core/camera_encoding.hpp"
#include "omnidso/core/image.hpp"
#include "omnidso/core/image_ops.hpp"

namespace omnidso {

// The number of pyramid levels coarse-to-fine alignment should use for a w × h image: a level
// is added while the current coarsest one has more than `min_coarsest_pixels` pixels (DSO's
// rule, 5000), at most max_levels. 480×480 and 640×480 get 4 levels (coarsest 60×60, 80×60),
// 752×480 gets 5 (47×30), KITTI's 1241×376 5 (77×23).
//
// DSO also stops at an odd side; here a level halves with the floor (downsample2x2 drops the
// last row or column, and every other pixel keeps its place, (x + ½)/2 − ½), so an odd side
// needs no stop. With it KITTI's 1241-pixel-wide images had one level and its 1226 × 370 ones
// two: a 120-frame render of the project's room at 1241 × 376 never initialised (the
// alignment lost by the second frame, photometric error 38–49), and reads 0.028 % of the path
// with 4 levels (docs/performance.md, "Odd image sides").
//
// Why not a fixed 5: on a 480×480 fisheye image whose content is the inscribed circle, the
// fifth level is 30×30 with a content disc 13 pixels in radius, a third of it touched by the
// black border; alignment there locked onto wrong rotations and the odometry lost its
// rotation and then its scale on sequences of an independent renderer, while 4 levels (or the
// same images upsampled 2×) tracked them (docs/performance.md, "Pyramid depth").
int pyramidLevelsForImage(int width, int height, int min_coarsest_pixels = 5000,
                          int max_levels = 6);

class ImagePyramid {
 public:
  static constexpr int kDefaultNumLevels = 5;
  // The coarsest level must be at least this wide and high: central differences and a
  // bilinear cell need two pixels along each axis.
  static constexpr int kMinCoarsestSize = 2;

  // Throws omnidso::Error if num_levels < 1 or the coarsest level would be smaller than
  // kMinCoarsestSize along either axis.
  // content (optional): where each level has image content (contentPyramid of
  // content_mask.hpp; at least num_levels masks of the levels' sizes), shared by every
  // frame of a camera; the residuals reject target samples that leave it.
  // encoding (optional): the camera's encoding of the levels' intensities
  // (camera_encoding.hpp), whose slope s = ∂I/∂E each level then offers (encodingSlope).
  // Throws omnidso::Error if its vignette does not fit the levels.
  explicit ImagePyramid(ImageF level0, int num_levels = kDefaultNumLevels,
                        std::shared_ptr<const std::vector<Mask>> content = nullptr,
                        std::shared_ptr<const CameraEncoding> encoding = nullptr);

  int numLevels() const { return static_cast<int>(levels_.size()); }
  const ImageF& level(int index) const;
  const ImageGradients& gradients(int index) const;
  // The content mask of a level, or nullptr when the whole image is content.
  const Mask* content(int index) const;
  // s = ∂I/∂E of a level (CameraEncoding::slope), or nullptr without an encoding (or with a
  // linear one). Computed on first use, once, from any thread: only the frames that host
  // residuals (keyframes, the initialiser's first frame) ever need it.
  const ImageF* encodingSlope(int index) const;

 private:
  std::vector<ImageF> levels_;
  std::vector<ImageGradients> gradients_;
  std::shared_ptr<const std::vector<Mask>> content_;
  struct EncodingSlopes;  // the encoding, the levels' slopes and their once-flags
  std::shared_ptr<EncodingSlopes> encoding_slopes_;  // null without an encoding
};

}  // namespace omnidso
