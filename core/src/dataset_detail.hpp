#pragma once
// Internals shared by the dataset readers (dataset.cc, dataset_tum.cc, dataset_asl.cc,
// dataset_kitti.cc).

#include <omnidso/core/dataset.hpp>

#include <optional>
#include <string>
#include <vector>

namespace omnidso::dataset_detail {

// The layout-specific readers fill frames, calibration, photometric and ground-truth
// paths, and list the frames whose image is missing (image_path: where it was looked for)
// apart; openDataset() then refuses or drops those, checks timestamps and reads the first
// image's size.
struct LayoutIndex {
  DatasetIndex index;
  std::vector<DatasetFrame> missing_images;
};
// openDataset() without the translation of std::filesystem errors.
DatasetIndex openDatasetIndex(const std::string& path, const DatasetOpenOptions& options);

LayoutIndex readTumIndex(const std::string& root);
LayoutIndex readAslIndex(const std::string& root);
LayoutIndex readKittiIndex(const std::string& root);

// Splits a line on whitespace and/or commas.
std::vector<std::string> splitFields(const std::string& line);

// Parses a number; throws fileError(file, line, ...) naming the field when it is not one.
double parseNumber(const std::string& text, const std::string& file, int line,
                   const std::string& what);

// One line of DSO's times.txt, `ID TIMESTAMP_S [EXPOSURE_MS]` (the TUM layout's index, and
// TUM VI's dso/cam0/times.txt). exposure_ms is 0 when the column is absent.
struct TimesLine {
  std::string id;
  double timestamp_s = 0;
  double exposure_ms = 0;
};
// nullopt for blank and '#' comment lines; throws fileError(file, line, ...) for a wrong
// field count, a field that is not a number, or a negative exposure.
std::optional<TimesLine> parseTimesLine(const std::string& line, const std::string& file,
                                        int line_number);

}  // namespace omnidso::dataset_detail
