#pragma once
// Where an image has content: fisheye and other wide-angle images hold the scene in a disc
// (or a rounded frame) and are black outside it, although the camera model's domain goes on
// beyond (UCM with ξ ≈ 1 is defined up to ≈ 160° from the axis). That black region is not
// "dark scene": its edge is fixed in the image however the camera moves. Left in, the edge
// enters pixel selection, the epipolar search and, through the pyramid's averaging, every
// coarse level of tracking and initialisation — and a static edge around the whole image is
// explained best by no motion, or by a roll about the optical axis, which leaves a circle
// unchanged. On the independent renderer's 190° sequences it made the initialiser report a
// 2.5° roll for a 7.3° yaw and locked the tracker onto wrong rotations (docs/performance.md,
// "Finding the scale collapse").
//
// detectContentMask: a pixel lies outside the content when its raw value is at most
// `black_level` in every one of the frames given AND it is connected (4-neighbourhood)
// through such pixels to the image border. A dark region inside the image is never removed,
// and a scene that is merely dark at the border is kept as soon as one frame shows it
// brighter. Returns an all-content mask when the outside would cover more than
// `max_outside_fraction` of the image (an all-black start, not a lens border). A lens's disc
// can fill little of its frame: a 190° view with ξ = 1.1 and f = 170 px is a 334-pixel disc,
// 38 % of its 480 × 480 frame. The bound was 0.6 and dropped that mask, and with it the
// content checks, the full image's error grew 4–6× (docs/performance.md, "A small image
// circle").
//
// contentExtent: the width and height of the smallest axis-aligned box holding every content
// pixel ({0, 0} when there is none) — the size of the image that DSO's flow rule for keyframes
// is relative to: its frames are filled by content, a fisheye's disc is not.
//
// erodeContent: removes every pixel within `radius` pixels (Chebyshev distance) of a
// non-content pixel inside the image; the image border itself does not erode.
//
// contentPyramid: the content of every level of an ImagePyramid built from images with this
// content: a level-L pixel is content when all four level-(L−1) pixels its 2×2 mean averages
// are (sizes halve with floor, as the pyramid's). A coarse pixel that mixes scene and
// surround is not content. Samplers check it for every target sample (interpolation.hpp,
// cellIsContent): a target projection that leaves the image circle compares the pattern with
// the black surround, which favours the motion that keeps it inside — under rotation, less
// rotation.

#include <omnidso/core/image.hpp>
#include <vector>

namespace omnidso {

Mask detectContentMask(const std::vector<const ImageU16*>& frames, int black_level,
                       double max_outside_fraction = 0.9);

Mask erodeContent(const Mask& content, int radius);

std::vector<Mask> contentPyramid(const Mask& level0, int num_levels);

struct ContentExtent {
  int width = 0;
  int height = 0;
};
ContentExtent contentExtent(const Mask& content);

}  // namespace omnidso
