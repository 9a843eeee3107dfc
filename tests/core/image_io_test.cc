#include "omnidso/core/image_io.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <string>

#include "core/temp_dir.hpp"
#include "omnidso/core/error.hpp"
#include "test_data.hpp"

namespace omnidso {
namespace {

template <typename Pixel>
Image<Pixel> randomImage(int w, int h, int max_value, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> value(0, max_value);
  Image<Pixel> img(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) img(u, v) = static_cast<Pixel>(value(rng));
  return img;
}

// Expects `call` to throw omnidso::Error whose message names `path`.
template <typename Call>
void expectErrorNaming(const std::string& path, Call call) {
  try {
    call();
    ADD_FAILURE() << "no omnidso::Error for " << path;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(ImageIo, EightBitRoundTrip) {
  const test::TempDir dir;
  const ImageU8 img = randomImage<std::uint8_t>(37, 21, 255, 1);
  const std::string path = dir.file("img8.png");
  writeImage(path, img);
  EXPECT_EQ(readImageU8(path), img);  // PNG is lossless
  const RawImage raw = readRawImage(path);
  EXPECT_EQ(raw.bit_depth, 8);
  const ImageU16 wide = readImageU16(path);  // raw values, not rescaled
  ASSERT_EQ(wide.width(), img.width());
  for (std::size_t i = 0; i < img.size(); ++i) {
    ASSERT_EQ(wide.data()[i], img.data()[i]);
    ASSERT_EQ(raw.pixels.data()[i], img.data()[i]);
  }
}

TEST(ImageIo, SixteenBitRoundTrip) {
  const test::TempDir dir;
  const ImageU16 img = randomImage<std::uint16_t>(19, 33, 65535, 2);
  const std::string path = dir.file("img16.png");
  writeImage(path, img);
  const RawImage raw = readRawImage(path);
  EXPECT_EQ(raw.bit_depth, 16);
  EXPECT_EQ(raw.pixels, img);
  EXPECT_EQ(readImageU16(path), img);
}

TEST(ImageIo, ToFloatKeepsValues) {
  const ImageU8 img = randomImage<std::uint8_t>(5, 4, 255, 3);
  const ImageF f = toFloat(img);
  for (std::size_t i = 0; i < img.size(); ++i) EXPECT_EQ(f.data()[i], img.data()[i]);
}

TEST(ImageIo, MissingFileErrorNamesPath) {
  const test::TempDir dir;
  const std::string path = dir.file("does_not_exist.png");
  expectErrorNaming(path, [&] { readImageU8(path); });
  expectErrorNaming(path, [&] { readRawImage(path); });
}

TEST(ImageIo, UndecodableFileErrorNamesPath) {
  const test::TempDir dir;
  const std::string path = dir.file("not_an_image.png");
  std::ofstream(path) << "this is text, not a PNG\n";
  expectErrorNaming(path, [&] { readImageU16(path); });
}

TEST(ImageIo, UnwritablePathErrorNamesPath) {
  const test::TempDir dir;
  const std::string path = dir.file("no_such_dir/img.png");
  expectErrorNaming(path, [&] { writeImage(path, ImageU8(4, 4)); });
}

TEST(ImageIo, RealColourJpegBecomesGrey) {
  const auto data = test::sharedDataDir("fisheye_calibration_jy");
  if (!data) GTEST_SKIP() << test::missingDataMessage("fisheye_calibration_jy");
  // A 3-channel 1280×800 JPEG (README of the data set).
  const RawImage raw = readRawImage((*data / "left" / "stereo_pair_000.jpg").string());
  EXPECT_EQ(raw.bit_depth, 8);
  EXPECT_EQ(raw.pixels.width(), 1280);
  EXPECT_EQ(raw.pixels.height(), 800);
}

}  // namespace
}  // namespace omnidso
