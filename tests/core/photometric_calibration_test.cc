#include "omnidso/core/photometric_calibration.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/temp_dir.hpp"
#include "omnidso/core/error.hpp"
#include "support/reference_image_preparation.hpp"
#include "test_data.hpp"

namespace omnidso {
namespace {

// A gamma-like inverse response G⁻¹(k) = 255·(k/255)^2.2 + k/255 (strictly increasing).
InverseResponse gammaInverseResponse() {
  InverseResponse table;
  for (int k = 0; k < kResponseSize; ++k) {
    table[k] = 255.0 * std::pow(k / 255.0, 2.2) + k / 255.0;
  }
  return table;
}

// A radial vignette 1 − 0.5·(r/r_max)², so V ∈ [0.5, 1].
ImageF radialVignette(int w, int h) {
  ImageF v(w, h);
  const double cx = (w - 1) / 2.0, cy = (h - 1) / 2.0;
  const double r_max_sq = cx * cx + cy * cy;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      v(x, y) = static_cast<float>(1.0 - 0.5 * ((x - cx) * (x - cx) + (y - cy) * (y - cy)) /
                                             r_max_sq);
  return v;
}

// Writes `line` as the only line of a pcalib file and expects readPcalib to throw an
// omnidso::Error containing the path and every string in `expected`.
void expectPcalibError(const test::TempDir& dir, const std::string& line,
                       const std::vector<std::string>& expected) {
  const std::string path = dir.file("pcalib.txt");
  std::ofstream(path) << line << "\n";
  try {
    readPcalib(path);
    ADD_FAILURE() << "no error for pcalib line: " << line.substr(0, 40) << "...";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    for (const std::string& s : expected) EXPECT_NE(message.find(s), std::string::npos) << message;
  }
}

std::string tableLine(const InverseResponse& table) {
  std::ostringstream out;
  out.precision(17);
  for (int k = 0; k < kResponseSize; ++k) out << (k ? " " : "") << table[k];
  return out.str();
}

TEST(PhotometricCalibration, ResponseInvertsInverseResponse) {
  const PhotometricCalibration calib(gammaInverseResponse(), ImageF());
  // Both directions are the same piecewise-linear map, so they invert each other exactly
  // up to double rounding (slopes here are between 0.004 and 2.2 → errors ≪ 1e-9).
  for (double x = 0.0; x <= 255.0; x += 0.37) {
    EXPECT_NEAR(calib.response(calib.inverseResponse(x)), x, 1e-9);
  }
  for (double e = 0.0; e <= 256.0; e += 0.91) {
    EXPECT_NEAR(calib.inverseResponse(calib.response(e)), e, 1e-9);
  }
  // Outside G⁻¹'s range G saturates.
  EXPECT_EQ(calib.response(-5.0), 0.0);
  EXPECT_EQ(calib.response(1e6), 255.0);
}

// responseSlopeTable: G′(E) = 1 / (G⁻¹ rise on the segment holding G(E)). Against the exact
// derivative of the gamma-like table, 1 / (G⁻¹)′(I) at I = G(E): a secant over one pixel value
// of a convex G⁻¹ differs from its tangent by at most (G⁻¹)″/(G⁻¹)′ ≈ 1.2 / I relatively
// (for the power 2.2), so the tolerance is 1.3 / I.
TEST(PhotometricCalibration, ResponseSlopeIsTheResponsesDerivative) {
  const PhotometricCalibration calib(gammaInverseResponse(), ImageF());
  const auto slope = calib.responseSlopeTable();
  for (int e = 2; e < 256; ++e) {
    const double i = calib.response(e);
    // G⁻¹(k) = 255 (k/255)^2.2 + k/255 → (G⁻¹)′(k) = 2.2 (k/255)^1.2 + 1/255.
    const double exact = 1.0 / (2.2 * std::pow(i / 255.0, 1.2) + 1.0 / 255.0);
    EXPECT_NEAR(slope[e], exact, exact * 1.3 / std::max(i, 1.0)) << "E = " << e;
  }
  const auto identity = PhotometricCalibration().responseSlopeTable();
  for (float s : identity) EXPECT_EQ(s, 1.f);
  // A flat stretch of G⁻¹ (k = 1..19 all 0) borrows the nearest rising segment's slope.
  InverseResponse flat = gammaInverseResponse();
  for (int k = 1; k < 20; ++k) flat[k] = 0.0;
  const auto with_flat = PhotometricCalibration(flat, ImageF()).responseSlopeTable();
  for (float s : with_flat) EXPECT_TRUE(std::isfinite(s) && s > 0.f);
  EXPECT_FLOAT_EQ(with_flat[0], static_cast<float>(1.0 / (flat[20] - flat[19])));
}

TEST(PhotometricCalibration, IdentityDefaults) {
  const PhotometricCalibration calib = PhotometricCalibration::fromFiles("", "");
  EXPECT_FALSE(calib.hasVignette());
  EXPECT_DOUBLE_EQ(calib.inverseResponse(17.5), 17.5);
  EXPECT_DOUBLE_EQ(calib.response(200.25), 200.25);
  RawImage raw{8, ImageU16(3, 2, 77)};
  const ImageF energy = calib.correct(raw);
  for (std::size_t i = 0; i < energy.size(); ++i) EXPECT_EQ(energy.data()[i], 77.0f);
}

TEST(PhotometricCalibration, PcalibWriteReadRoundTrip) {
  const test::TempDir dir;
  const InverseResponse table = gammaInverseResponse();
  writePcalib(dir.file("pcalib.txt"), table);
  EXPECT_EQ(readPcalib(dir.file("pcalib.txt")), table);  // 17 significant digits
}

TEST(PhotometricCalibration, MalformedPcalibErrorsNameFileAndIndex) {
  const test::TempDir dir;
  InverseResponse table = identityInverseResponse();
  // Wrong count: 255 values.
  std::string line = tableLine(table);
  expectPcalibError(dir, line.substr(0, line.rfind(' ')), {":1:", "found 255"});
  // Non-numeric value at index 7.
  std::string bad = tableLine(table);
  std::istringstream tokens(bad);
  std::ostringstream rebuilt;
  std::string token;
  for (int k = 0; tokens >> token; ++k) rebuilt << (k ? " " : "") << (k == 7 ? "abc" : token);
  expectPcalibError(dir, rebuilt.str(), {":1:", "index 7", "abc"});
  // Decreasing value at index 100.
  table[100] = 50.0;
  expectPcalibError(dir, tableLine(table), {":1:", "index 100"});
  // Empty file; missing file.
  expectPcalibError(dir, "", {"empty"});
  try {
    readPcalib(dir.file("missing.txt"));
    ADD_FAILURE() << "no error for a missing file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("missing.txt")), std::string::npos);
  }
}

TEST(PhotometricCalibration, VignetteNormalisedByMaximum) {
  const test::TempDir dir;
  ImageU16 raw(4, 3, 10000);
  raw(1, 1) = 40000;
  raw(3, 2) = 0;
  writeImage(dir.file("vignette.png"), raw);
  const ImageF v = readVignette(dir.file("vignette.png"));
  EXPECT_FLOAT_EQ(v(1, 1), 1.0f);
  EXPECT_FLOAT_EQ(v(0, 0), 0.25f);
  EXPECT_FLOAT_EQ(v(3, 2), 0.0f);
  // 8-bit vignettes normalise the same way.
  ImageU8 raw8(2, 2, 51);
  raw8(0, 1) = 204;
  writeImage(dir.file("vignette8.png"), raw8);
  EXPECT_FLOAT_EQ(readVignette(dir.file("vignette8.png"))(1, 1), 0.25f);
  // An all-zero vignette is rejected.
  writeImage(dir.file("zero.png"), ImageU8(2, 2, 0));
  EXPECT_THROW(readVignette(dir.file("zero.png")), Error);
}

TEST(PhotometricCalibration, VignetteWriteReadRoundTrip) {
  const test::TempDir dir;
  const ImageF vignette = radialVignette(40, 30);
  writeVignette(dir.file("vignette.png"), vignette);
  const ImageF back = readVignette(dir.file("vignette.png"));
  ASSERT_EQ(back.width(), 40);
  // Reading normalises by the maximum (just below 1: no pixel sits at the exact centre).
  const float maximum = *std::max_element(vignette.data(), vignette.data() + vignette.size());
  // Quantised to 16 bits relative to the maximum: half a step is 0.5/65535 ≈ 7.6e-6.
  for (std::size_t i = 0; i < back.size(); ++i) {
    EXPECT_NEAR(back.data()[i], vignette.data()[i] / maximum, 1e-5);
  }
}

TEST(PhotometricCalibration, CorrectRecoversIrradiance) {
  // Render raw = G(t·V·B) into 16 bits (value·257), then correct and divide by t.
  const int w = 24, h = 16;
  const double exposure = 2.5;
  const ImageF vignette = radialVignette(w, h);
  const PhotometricCalibration calib(gammaInverseResponse(), vignette, "test vignette");
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> irradiance_dist(1.0, 100.0);
  ImageF irradiance(w, h);
  RawImage raw{16, ImageU16(w, h)};
  for (std::size_t i = 0; i < irradiance.size(); ++i) {
    irradiance.data()[i] = static_cast<float>(irradiance_dist(rng));
    const double pixel = calib.response(exposure * vignette.data()[i] * irradiance.data()[i]);
    raw.pixels.data()[i] = static_cast<std::uint16_t>(std::lround(pixel * 257.0));
  }
  const ImageF energy = calib.correct(raw);
  const ImageF recovered = toIrradiance(energy, exposure);
  // Rounding to 16 bits moves the pixel value by ≤ 0.5/257 on the 8-bit scale; G⁻¹'s
  // steepest slope is max_k (G⁻¹(k+1) − G⁻¹(k)), and the error is then divided by
  // V ≥ 0.5 and t — plus float rounding of values ≤ 100 (1e-5).
  const InverseResponse& table = calib.inverseResponseTable();
  double max_slope = 0;
  for (int k = 0; k + 1 < kResponseSize; ++k) {
    max_slope = std::max(max_slope, table[k + 1] - table[k]);
  }
  const double bound = 0.5 / 257.0 * max_slope / 0.5 / exposure + 1e-4;
  for (std::size_t i = 0; i < recovered.size(); ++i) {
    ASSERT_NEAR(recovered.data()[i], irradiance.data()[i], bound) << "pixel " << i;
  }
}

TEST(PhotometricCalibration, EightBitIndexesTableAndZeroVignetteGivesZero) {
  ImageF vignette(2, 1, 0.5f);
  vignette(1, 0) = 0.0f;
  const InverseResponse table = gammaInverseResponse();
  const PhotometricCalibration calib(table, vignette);
  const ImageF energy = calib.correct(RawImage{8, ImageU16(2, 1, 200)});
  EXPECT_FLOAT_EQ(energy(0, 0), static_cast<float>(table[200] / 0.5));
  EXPECT_EQ(energy(1, 0), 0.0f);
}

// correct() reads G⁻¹ from tables of inverseResponse() per raw value: the result must be the
// same bits as evaluating inverseResponse() per pixel (support/reference_image_preparation.hpp)
// for 8 and 16 bits, with and without a vignette (with zeros in it), a response with a flat
// stretch and -0 (whose interpolation could round differently), and 8-bit values above 255.
bool sameBits(const ImageF& a, const ImageF& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(PhotometricCalibration, CorrectBitIdenticalToInverseResponsePerPixel) {
  InverseResponse odd = gammaInverseResponse();
  odd[0] = -0.0;
  for (int k = 1; k < 20; ++k) odd[k] = 0.0;  // flat, then the gamma curve
  std::mt19937 rng(33);
  for (const int size : {16, 300}) {  // 300² > 65536: the 16-bit table is used
    ImageF vignette = radialVignette(size, size);
    for (int i = 0; i < size; ++i) vignette(i, i) = 0.0f;
    for (const InverseResponse& table : {gammaInverseResponse(), odd, identityInverseResponse()})
      for (const ImageF& v : {ImageF(), vignette}) {
        const PhotometricCalibration calib(table, v);
        for (const int bits : {8, 16}) {
          RawImage raw{bits, ImageU16(size, size)};
          std::uniform_int_distribution<int> value(0, bits == 8 ? 300 : 65535);
          for (std::size_t i = 0; i < raw.pixels.size(); ++i)
            raw.pixels.data()[i] = static_cast<std::uint16_t>(value(rng));
          EXPECT_TRUE(sameBits(calib.correct(raw), reference::correct(calib, raw)))
              << bits << " bits, " << size << "², vignette " << !v.empty();
        }
      }
  }
}

TEST(PhotometricCalibration, CorrectBitIdenticalOnRealImages) {
  const auto dir = test::sharedDataDir("euroc_v101_static_clip");
  if (!dir) GTEST_SKIP() << test::missingDataMessage("euroc_v101_static_clip");
  const std::string path =
      (*dir / "mav0/cam0/data/1403715277862142976.png").string();
  const RawImage raw = readRawImage(path);
  const ImageF vignette = radialVignette(raw.pixels.width(), raw.pixels.height());
  for (const ImageF& v : {ImageF(), vignette}) {
    const PhotometricCalibration calib(gammaInverseResponse(), v);
    EXPECT_TRUE(sameBits(calib.correct(raw), reference::correct(calib, raw)));
  }
}

TEST(PhotometricCalibration, VignetteSizeMismatchNamesVignette) {
  const PhotometricCalibration calib(identityInverseResponse(), ImageF(4, 4, 1.0f),
                                     "/data/seq/vignette.png");
  try {
    calib.correct(RawImage{8, ImageU16(5, 4)});
    ADD_FAILURE() << "no error for a 5x4 image with a 4x4 vignette";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/data/seq/vignette.png"), std::string::npos);
  }
  EXPECT_NO_THROW(calib.checkImageSize(4, 4));
}

TEST(PhotometricCalibration, NonPositiveExposureThrows) {
  EXPECT_THROW(toIrradiance(ImageF(2, 2), 0.0), Error);
  EXPECT_THROW(toIrradiance(ImageF(2, 2), -1.0), Error);
}

}  // namespace
}  // namespace omnidso
