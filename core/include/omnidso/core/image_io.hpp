#pragma once
// Reading and writing greyscale images (PNG, JPEG, TIFF, ... — whatever OpenCV's imgcodecs
// decodes; OpenCV stays inside image_io.cc). Colour images are converted to grey
// (OpenCV's weights 0.299 R + 0.587 G + 0.114 B). A missing or undecodable file throws
// omnidso::Error naming the file.

#include <string>

#include "omnidso/core/image.hpp"

namespace omnidso {

// A greyscale image as stored: bit_depth 8 (values 0..255) or 16 (0..65535), held in
// 16-bit pixels either way so that photometric correction sees the raw values.
struct RawImage {
  int bit_depth = 8;
  ImageU16 pixels;
};

// 8-bit grey. A 16-bit file is reduced to 8 bits by OpenCV (value / 256).
ImageU8 readImageU8(const std::string& path);

// Raw values, not rescaled: an 8-bit file gives 0..255, a 16-bit file 0..65535. Use
// readRawImage when the bit depth matters.
ImageU16 readImageU16(const std::string& path);

// 8- or 16-bit greyscale with its bit depth; other depths (float, 32-bit) throw.
RawImage readRawImage(const std::string& path);

// The format follows the extension; 16-bit images need a format that stores 16 bits
// (PNG, TIFF). Throws omnidso::Error naming the file if writing fails.
void writeImage(const std::string& path, const ImageU8& image);
void writeImage(const std::string& path, const ImageU16& image);

// Pixel values as float, unscaled (0..255).
ImageF toFloat(const ImageU8& image);

}  // namespace omnidso
