// detectContentMask / erodeContent (content_mask.hpp): the black surround of an image circle
// is found, dark regions inside are kept, an all-black start is not taken for a border, and
// erosion removes exactly the pixels within the Chebyshev radius of a hole.
#include <gtest/gtest.h>

#include <cmath>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

// A 64×48 frame: a disc of radius 20 about (32, 24) with value 100 (a black dot of radius 3
// at its centre), black (0) outside.
ImageU16 discFrame() {
  ImageU16 f(64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) {
      const double r = std::hypot(u - 32.0, v - 24.0);
      f(u, v) = r <= 20.0 && r > 3.0 ? 100 : 0;
    }
  return f;
}

TEST(ContentMask, FindsTheBlackSurroundButKeepsDarkRegionsInside) {
  const ImageU16 f = discFrame();
  const Mask m = detectContentMask({&f}, 5);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) {
      const double r = std::hypot(u - 32.0, v - 24.0);
      EXPECT_EQ(m(u, v), r <= 20.0 ? 1 : 0) << u << "," << v;  // the centre dot stays content
    }
}

// A pixel black in one frame but bright in another is content: the scene was only dark there.
TEST(ContentMask, APixelBrightInAnyFrameIsContent) {
  const ImageU16 dark = discFrame();
  ImageU16 lit = discFrame();
  lit(0, 0) = 50;
  const Mask m = detectContentMask({&dark, &lit}, 5);
  EXPECT_EQ(m(0, 0), 1);
  EXPECT_EQ(m(1, 0), 0);
}

TEST(ContentMask, AnAllBlackStartIsNotABorder) {
  ImageU16 black(64, 48);
  for (size_t i = 0; i < black.size(); ++i) black.data()[i] = 0;
  const Mask m = detectContentMask({&black}, 5);
  for (size_t i = 0; i < m.size(); ++i) EXPECT_EQ(m.data()[i], 1);
  EXPECT_THROW(detectContentMask({}, 5), Error);
}

TEST(ContentMask, ErosionRemovesTheChebyshevNeighbourhoodOfHolesOnly) {
  Mask m(20, 10);
  for (size_t i = 0; i < m.size(); ++i) m.data()[i] = 1;
  m(10, 5) = 0;
  const Mask e = erodeContent(m, 2);
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 20; ++u)
      EXPECT_EQ(e(u, v), std::abs(u - 10) <= 2 && std::abs(v - 5) <= 2 ? 0 : 1) << u << "," << v;
  // The image border is not a hole.
  Mask full(8, 8);
  for (size_t i = 0; i < full.size(); ++i) full.data()[i] = 1;
  const Mask f = erodeContent(full, 3);
  for (size_t i = 0; i < f.size(); ++i) EXPECT_EQ(f.data()[i], 1);
}

}  // namespace
}  // namespace omnidso
