// Image sizes from file headers: `omnidso dataset info` checks thousands of frames in about
// a second, which decoding them all would not allow.
#include <omnidso/core/dataset.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include <omnidso/core/error.hpp>

namespace omnidso {
namespace {

int bigEndian16(const unsigned char* b) { return (b[0] << 8) | b[1]; }
long bigEndian32(const unsigned char* b) {
  return (static_cast<long>(b[0]) << 24) | (b[1] << 16) | (b[2] << 8) | b[3];
}

// PNG: 8-byte signature, then the IHDR chunk (length, "IHDR", width, height; big-endian).
bool pngSize(std::ifstream& in, ImageSize& size) {
  std::array<unsigned char, 24> head{};
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(head.data()), head.size())) return false;
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G',
                                                              0x0D, 0x0A, 0x1A, 0x0A};
  if (!std::equal(kSignature.begin(), kSignature.end(), head.begin())) return false;
  if (std::string(head.begin() + 12, head.begin() + 16) != "IHDR") return false;
  size.width = static_cast<int>(bigEndian32(&head[16]));
  size.height = static_cast<int>(bigEndian32(&head[20]));
  return size.width > 0 && size.height > 0;
}

// A complete file ends with its end marker: PNG's IEND chunk (length 0, "IEND", CRC
// AE 42 60 82) or JPEG's EOI (FF D9). Catches truncated files (an interrupted copy)
// without decoding.
bool endsWith(std::ifstream& in, const std::vector<unsigned char>& tail) {
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff length = in.tellg();
  if (length < static_cast<std::streamoff>(tail.size())) return false;
  in.seekg(length - static_cast<std::streamoff>(tail.size()));
  std::vector<unsigned char> bytes(tail.size());
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()))) {
    return false;
  }
  return bytes == tail;
}

// JPEG: walk the marker segments (FF xx, 16-bit length) up to a start-of-frame marker,
// whose payload is precision (1 byte), height (2), width (2).
bool jpegSize(std::ifstream& in, ImageSize& size) {
  in.seekg(0);
  unsigned char soi[2];
  if (!in.read(reinterpret_cast<char*>(soi), 2) || soi[0] != 0xFF || soi[1] != 0xD8) {
    return false;
  }
  for (int segment = 0; segment < 1000; ++segment) {
    int byte = in.get();
    if (byte != 0xFF) return false;
    int marker = in.get();
    while (marker == 0xFF) marker = in.get();  // fill bytes
    if (marker == EOF) return false;
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;  // no length
    unsigned char length_bytes[2];
    if (!in.read(reinterpret_cast<char*>(length_bytes), 2)) return false;
    const int length = bigEndian16(length_bytes);
    if (length < 2) return false;
    const bool start_of_frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 &&
                                marker != 0xC8 && marker != 0xCC;
    if (start_of_frame) {
      unsigned char sof[5];
      if (!in.read(reinterpret_cast<char*>(sof), 5)) return false;
      size.height = bigEndian16(&sof[1]);
      size.width = bigEndian16(&sof[3]);
      return size.width > 0 && size.height > 0;
    }
    in.seekg(length - 2, std::ios::cur);
  }
  return false;
}

}  // namespace

ImageSize readImageSize(const std::string& image_path) {
  std::ifstream in(image_path, std::ios::binary);
  if (!in) throw fileError(image_path, "image cannot be opened");
  ImageSize size;
  if (pngSize(in, size)) {
    if (!endsWith(in, {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82})) {
      throw fileError(image_path, "PNG image is truncated (no IEND chunk at its end)");
    }
    return size;
  }
  in.clear();
  if (jpegSize(in, size)) {
    // Some encoders pad after EOI; accept the marker within the last 4 bytes.
    bool complete = false;
    for (int pad = 0; pad <= 2 && !complete; ++pad) {
      std::vector<unsigned char> tail = {0xFF, 0xD9};
      tail.resize(2 + static_cast<size_t>(pad), 0);
      complete = endsWith(in, tail);
    }
    if (!complete) throw fileError(image_path, "JPEG image is truncated (no end marker)");
    return size;
  }
  // Other formats: decode (slow, but only for formats the datasets here do not use).
  const cv::Mat image = cv::imread(image_path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw fileError(image_path, "image is unreadable (not PNG/JPEG or corrupt)");
  return {image.cols, image.rows};
}

}  // namespace omnidso
