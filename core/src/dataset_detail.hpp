#pragma once
// Internals shared by the dataset readers (dataset.cc, dataset_tum.cc, dataset_asl.cc).

#include <omnidso/core/dataset.hpp>

#include <string>
#include <vector>

namespace omnidso::dataset_detail {

// The layout-specific readers fill frames, calibration, photometric and ground-truth
// paths; openDataset() then checks timestamps and reads the first image's size.
DatasetIndex readTumIndex(const std::string& root);
DatasetIndex readAslIndex(const std::string& root);

// Splits a line on whitespace and/or commas.
std::vector<std::string> splitFields(const std::string& line);

// Parses a number; throws fileError(file, line, ...) naming the field when it is not one.
double parseNumber(const std::string& text, const std::string& file, int line,
                   const std::string& what);

}  // namespace omnidso::dataset_detail
