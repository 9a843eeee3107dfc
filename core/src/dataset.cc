// Layout detection and the checks common to every dataset layout.
#include <omnidso/core/dataset.hpp>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <omnidso/core/error.hpp>
#include <omnidso/core/number_text.hpp>

#include "dataset_detail.hpp"

namespace omnidso {
namespace fs = std::filesystem;

namespace dataset_detail {

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string current;
  for (const char c : line) {
    if (c == ',' || c == ' ' || c == '\t' || c == '\r') {
      if (!current.empty()) fields.push_back(current);
      current.clear();
    } else {
      current.push_back(c);
    }
  }
  if (!current.empty()) fields.push_back(current);
  return fields;
}

double parseNumber(const std::string& text, const std::string& file, int line,
                   const std::string& what) {
  if (const std::optional<double> value = parseWholeNumber(text)) return *value;
  throw fileError(file, line, fmt::format("{} '{}' is not a number", what, text));
}

std::optional<TimesLine> parseTimesLine(const std::string& line, const std::string& file,
                                        int line_number) {
  const std::vector<std::string> fields = splitFields(line);
  if (fields.empty() || fields[0][0] == '#') return std::nullopt;
  if (fields.size() < 2 || fields.size() > 3) {
    throw fileError(file, line_number,
                    fmt::format("expected 'ID TIMESTAMP_S [EXPOSURE_MS]', got {} fields",
                                fields.size()));
  }
  TimesLine parsed;
  parsed.id = fields[0];
  parsed.timestamp_s = parseNumber(fields[1], file, line_number, "timestamp");
  if (fields.size() == 3) {
    parsed.exposure_ms = parseNumber(fields[2], file, line_number, "exposure");
    if (parsed.exposure_ms < 0) throw fileError(file, line_number, "exposure time is negative");
  }
  return parsed;
}

namespace {

// "a.png (line 3), b.png (line 4), … and 7 more": enough to find them, short enough to read.
std::string listMissing(const std::vector<DatasetFrame>& missing) {
  constexpr std::size_t kListed = 5;
  std::string text;
  for (std::size_t i = 0; i < std::min(missing.size(), kListed); ++i) {
    text += fmt::format("{}{} (line {})", i ? ", " : "", missing[i].image_path,
                        missing[i].index_line);
  }
  if (missing.size() > kListed) text += fmt::format(" and {} more", missing.size() - kListed);
  return text;
}

// Missing images: one error naming the index file, the first line and the images; or, when
// asked, the frames dropped with a warning.
void handleMissingImages(const std::vector<DatasetFrame>& missing, bool skip,
                         DatasetIndex& index) {
  if (missing.empty()) return;
  const DatasetFrame& first = missing.front();
  const bool at_end = index.frames.empty() || first.index_line > index.frames.back().index_line;
  if (!skip) {
    const std::string what =
        missing.size() == 1
            ? fmt::format("image '{}' not found", first.image_path)
            : fmt::format("{} listed images not found{}: {}", missing.size(),
                          at_end ? " at the end of the list" : "", listMissing(missing));
    throw fileError(first.index_file, first.index_line,
                    what + " (omnidso run --skip-missing drops such frames)");
  }
  if (index.frames.empty()) {
    throw fileError(first.index_file, "none of the listed images exists: " + listMissing(missing));
  }
  index.warnings.push_back(fmt::format("{}: {} frame(s) dropped, their images are missing: {}",
                                       first.index_file, missing.size(), listMissing(missing)));
}

}  // namespace

}  // namespace dataset_detail

const char* datasetLayoutName(DatasetLayout layout) {
  switch (layout) {
    case DatasetLayout::kTum:
      return "tum";
    case DatasetLayout::kAsl:
      return "asl";
    case DatasetLayout::kKitti:
      return "kitti";
  }
  return "unknown";
}

DatasetIndex openDataset(const std::string& path, const DatasetOpenOptions& options) {
  try {
    return dataset_detail::openDatasetIndex(path, options);
  } catch (const fs::filesystem_error& e) {
    // A symbolic-link loop or an unreadable directory on the way: bad input like any other.
    const std::string culprit = e.path1().empty() ? path : e.path1().string();
    throw fileError(culprit, e.code().message());
  }
}

DatasetIndex dataset_detail::openDatasetIndex(const std::string& path,
                                              const DatasetOpenOptions& options) {
  if (!fs::is_directory(path)) throw fileError(path, "dataset directory not found");
  const fs::path root(path);
  dataset_detail::LayoutIndex layout;
  // KITTI before TUM: both have times.txt; images/ keeps a directory TUM.
  if (fs::is_directory(root / "image_0") && fs::exists(root / "calib.txt") &&
      !fs::exists(root / "images")) {
    layout = dataset_detail::readKittiIndex(path);
  } else if (fs::exists(root / "times.txt") || fs::exists(root / "images")) {
    layout = dataset_detail::readTumIndex(path);
  } else if (fs::exists(root / "mav0")) {
    layout = dataset_detail::readAslIndex(path);
  } else {
    throw fileError(path,
                    "not a dataset: expected times.txt and images/ (TUM layout), "
                    "mav0/cam0/data.csv (ASL layout) or times.txt, image_0/ and calib.txt "
                    "(KITTI odometry layout)");
  }
  DatasetIndex& index = layout.index;
  dataset_detail::handleMissingImages(layout.missing_images, options.skip_missing_images, index);
  // Strictly increasing timestamps: the odometry and the evaluation order frames by time.
  for (std::size_t i = 1; i < index.frames.size(); ++i) {
    const DatasetFrame& previous = index.frames[i - 1];
    const DatasetFrame& frame = index.frames[i];
    if (!(frame.timestamp_s > previous.timestamp_s)) {
      throw fileError(frame.index_file, frame.index_line,
                      fmt::format("timestamp {:.9f} s is not after the previous one ({:.9f} s, "
                                  "line {})",
                                  frame.timestamp_s, previous.timestamp_s,
                                  previous.index_line));
    }
  }
  const DatasetFrame& first = index.frames.front();
  ImageSize size;
  try {
    size = readImageSize(first.image_path);
  } catch (const Error& e) {
    throw fileError(first.index_file, first.index_line, e.what());
  }
  index.width = size.width;
  index.height = size.height;
  return std::move(index);
}

void verifyDatasetImages(const DatasetIndex& index, bool decode) {
  for (size_t i = 0; i < index.frames.size(); ++i) {
    const DatasetFrame& frame = index.frames[i];
    if (decode) {
      readDatasetFrame(index, i);
      continue;
    }
    ImageSize size;
    try {
      size = readImageSize(frame.image_path);
    } catch (const Error& e) {
      throw fileError(frame.index_file, frame.index_line, e.what());
    }
    if (size.width != index.width || size.height != index.height) {
      throw fileError(frame.index_file, frame.index_line,
                      fmt::format("image {} is {}x{}, but the first image is {}x{}",
                                  frame.image_path, size.width, size.height, index.width,
                                  index.height));
    }
  }
}

RawImage readDatasetRawFrame(const DatasetFrame& frame) {
  try {
    return readRawImage(frame.image_path);
  } catch (const Error& e) {
    throw fileError(frame.index_file, frame.index_line, e.what());
  }
}

ImageU8 readDatasetFrame(const DatasetIndex& index, std::size_t i) {
  const DatasetFrame& frame = index.frames.at(i);
  const cv::Mat raw = cv::imread(frame.image_path, cv::IMREAD_UNCHANGED);
  if (raw.empty()) {
    throw fileError(frame.index_file, frame.index_line,
                    fmt::format("image {} is unreadable", frame.image_path));
  }
  if (raw.cols != index.width || raw.rows != index.height) {
    throw fileError(frame.index_file, frame.index_line,
                    fmt::format("image {} is {}x{}, but the first image is {}x{}",
                                frame.image_path, raw.cols, raw.rows, index.width,
                                index.height));
  }
  cv::Mat grey = raw;
  if (raw.channels() == 3) cv::cvtColor(raw, grey, cv::COLOR_BGR2GRAY);
  if (raw.channels() == 4) cv::cvtColor(raw, grey, cv::COLOR_BGRA2GRAY);
  cv::Mat grey8 = grey;
  // 16-bit → 8-bit: 65535/255 = 257 maps full scale to full scale.
  if (grey.depth() == CV_16U) grey.convertTo(grey8, CV_8U, 1.0 / 257.0);
  ImageU8 out(grey8.cols, grey8.rows);
  for (int v = 0; v < grey8.rows; ++v) {
    const std::uint8_t* src = grey8.ptr<std::uint8_t>(v);
    std::copy(src, src + grey8.cols, out.row(v));
  }
  return out;
}

double datasetDuration(const DatasetIndex& index) {
  if (index.frames.size() < 2) return 0.0;
  return index.frames.back().timestamp_s - index.frames.front().timestamp_s;
}

double datasetFrameRate(const DatasetIndex& index) {
  const double duration = datasetDuration(index);
  return duration > 0 ? static_cast<double>(index.frames.size() - 1) / duration : 0.0;
}

}  // namespace omnidso
