// detectContentMask / contentExtent / erodeContent / contentPyramid (content_mask.hpp): the
// black surround of an image circle is found, also around a small one, dark regions inside are
// kept, an all-black start is not taken for a border, the content's box is measured, erosion
// removes exactly the pixels within the Chebyshev radius of a hole, and a coarse level's pixel
// is content only when every pixel it averages is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <omnidso/core/content_mask.hpp>
#include <omnidso/core/error.hpp>
#include <omnidso/core/pyramid.hpp>

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

// A lens whose disc fills little of its frame still has a border: a disc of radius 15 covers
// 23 % of the 64×48 frame (the independent renderer's ξ = 1.1, f = 170 render: 38 %). With the
// old bound (outside ≤ 60 %) it was taken for an all-black start and dropped.
TEST(ContentMask, ASmallImageCircleIsStillABorder) {
  ImageU16 f(64, 48);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) f(u, v) = std::hypot(u - 32.0, v - 24.0) <= 15.0 ? 100 : 0;
  const Mask m = detectContentMask({&f}, 5);
  size_t content = 0;
  for (size_t i = 0; i < m.size(); ++i) content += m.data()[i];
  EXPECT_LT(content, m.size() / 4);
  EXPECT_EQ(m(32, 24), 1);
  EXPECT_EQ(m(0, 0), 0);
  EXPECT_EQ(m(32, 24 - 16), 0);
}

// The content's box: the disc of radius 20 about (32, 24) spans u 12 … 52 and v 4 … 44.
TEST(ContentMask, ExtentIsTheContentsBoundingBox) {
  const ImageU16 f = discFrame();
  const ContentExtent disc = contentExtent(detectContentMask({&f}, 5));
  EXPECT_EQ(disc.width, 41);
  EXPECT_EQ(disc.height, 41);
  Mask all(64, 48), none(64, 48);
  std::fill(all.data(), all.data() + all.size(), std::uint8_t{1});
  std::fill(none.data(), none.data() + none.size(), std::uint8_t{0});
  EXPECT_EQ(contentExtent(all).width, 64);
  EXPECT_EQ(contentExtent(all).height, 48);
  EXPECT_EQ(contentExtent(none).width, 0);
  EXPECT_EQ(contentExtent(none).height, 0);
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

// Level L of the content pyramid against its definition: a pixel is content iff the whole
// 2^L × 2^L block of level-0 pixels under it is (the pyramid's means nest), on odd sizes too.
TEST(ContentPyramid, ACoarsePixelIsContentOnlyWhenEveryPixelUnderItIs) {
  const ImageU16 frame = discFrame();
  const Mask level0 = detectContentMask({&frame}, 0);
  Mask odd(61, 45);  // floor halving: 30×22, 15×11
  for (int v = 0; v < odd.height(); ++v)
    for (int u = 0; u < odd.width(); ++u) odd(u, v) = level0(u, v);
  for (const Mask* m : std::vector<const Mask*>{&level0, &odd}) {
    const std::vector<Mask> levels = contentPyramid(*m, 3);
    ASSERT_EQ(levels.size(), 3u);
    int coarse_content = 0;
    for (int l = 0; l < 3; ++l) {
      EXPECT_EQ(levels[l].width(), m->width() >> l);
      EXPECT_EQ(levels[l].height(), m->height() >> l);
      for (int v = 0; v < levels[l].height(); ++v)
        for (int u = 0; u < levels[l].width(); ++u) {
          bool all = true;
          for (int y = v << l; y < (v + 1) << l; ++y)
            for (int x = u << l; x < (u + 1) << l; ++x) all = all && (*m)(x, y) != 0;
          ASSERT_EQ(levels[l](u, v) != 0, all) << "level " << l << " at " << u << "," << v;
          coarse_content += l == 2 && all;
        }
    }
    EXPECT_GT(coarse_content, 0);  // the disc survives at level 2
  }
  EXPECT_THROW(contentPyramid(level0, 0), Error);
}

TEST(ContentPyramid, APyramidHandsOutItsLevelsMasksAndRefusesWrongSizes) {
  const ImageU16 frame = discFrame();
  auto content = std::make_shared<const std::vector<Mask>>(
      contentPyramid(detectContentMask({&frame}, 0), 3));
  const ImagePyramid plain(ImageF(64, 48, 1.f), 3);
  EXPECT_EQ(plain.content(1), nullptr);
  const ImagePyramid masked(ImageF(64, 48, 1.f), 3, content);
  for (int l = 0; l < 3; ++l) EXPECT_EQ(masked.content(l), &(*content)[l]);
  EXPECT_THROW(masked.content(3), Error);
  EXPECT_THROW(ImagePyramid(ImageF(64, 48, 1.f), 4, content), Error);  // too few masks
  EXPECT_THROW(ImagePyramid(ImageF(66, 48, 1.f), 3, content), Error);  // other sizes
}

}  // namespace
}  // namespace omnidso
