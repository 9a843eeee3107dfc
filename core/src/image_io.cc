#include "omnidso/core/image_io.hpp"

#include <cstring>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "omnidso/core/error.hpp"

namespace omnidso {
namespace {

// Reads a greyscale cv::Mat with the given imread flags; throws naming the file when it
// is missing or cannot be decoded.
cv::Mat readGrey(const std::string& path, int flags) {
  std::error_code status_error;  // a symbolic-link loop is bad input, not an exception escape
  if (!std::filesystem::is_regular_file(path, status_error)) {
    throw fileError(path, status_error ? "cannot read image: " + status_error.message()
                                       : std::string("image file not found"));
  }
  cv::Mat mat;
  try {
    mat = cv::imread(path, flags);
  } catch (const cv::Exception& e) {
    throw fileError(path, std::string("cannot decode image: ") + e.what());
  }
  if (mat.empty()) throw fileError(path, "cannot decode image");
  return mat;
}

template <typename Pixel>
Image<Pixel> fromMat(const cv::Mat& mat) {
  Image<Pixel> out(mat.cols, mat.rows);
  for (int v = 0; v < mat.rows; ++v) {
    const std::size_t row_bytes = sizeof(Pixel) * static_cast<std::size_t>(mat.cols);
    std::memcpy(out.row(v), mat.ptr<Pixel>(v), row_bytes);
  }
  return out;
}

template <typename Pixel>
void writeMat(const std::string& path, const Image<Pixel>& image, int cv_type) {
  // cv::Mat does not modify the data it wraps here; imwrite only reads it.
  const cv::Mat mat(image.height(), image.width(), cv_type,
                    const_cast<Pixel*>(image.data()));
  bool ok = false;
  try {
    ok = cv::imwrite(path, mat);
  } catch (const cv::Exception& e) {
    throw fileError(path, std::string("cannot write image: ") + e.what());
  }
  if (!ok) throw fileError(path, "cannot write image");
}

}  // namespace

ImageU8 readImageU8(const std::string& path) {
  return fromMat<std::uint8_t>(readGrey(path, cv::IMREAD_GRAYSCALE));
}

ImageU16 readImageU16(const std::string& path) { return readRawImage(path).pixels; }

RawImage readRawImage(const std::string& path) {
  const cv::Mat mat = readGrey(path, cv::IMREAD_GRAYSCALE | cv::IMREAD_ANYDEPTH);
  RawImage raw;
  if (mat.depth() == CV_8U) {
    cv::Mat wide;
    mat.convertTo(wide, CV_16U);  // raw values, no scaling
    raw.bit_depth = 8;
    raw.pixels = fromMat<std::uint16_t>(wide);
  } else if (mat.depth() == CV_16U) {
    raw.bit_depth = 16;
    raw.pixels = fromMat<std::uint16_t>(mat);
  } else {
    throw fileError(path, "unsupported pixel depth (only 8- and 16-bit greyscale)");
  }
  return raw;
}

void writeImage(const std::string& path, const ImageU8& image) {
  writeMat(path, image, CV_8UC1);
}

void writeImage(const std::string& path, const ImageU16& image) {
  writeMat(path, image, CV_16UC1);
}

ImageF toFloat(const ImageU8& image) {
  ImageF out(image.width(), image.height());
  const std::size_t n = image.size();
  for (std::size_t i = 0; i < n; ++i) out.data()[i] = static_cast<float>(image.data()[i]);
  return out;
}

}  // namespace omnidso
