#pragma once
// Internal to the text calibration readers (DSO's camera.txt, KITTI's calib.txt): a line's
// whitespace-separated tokens, and the tokens read as finite numbers with errors naming the
// file and line.

#include <cstddef>
#include <string>
#include <vector>

namespace omnidso::detail {

std::vector<std::string> textTokens(const std::string& line);

// tokens[first…] as numbers; throws omnidso::Error naming `path` and `line_no` for the first
// that is not a number or not finite, its message prefixed by `label` (e.g. "P0: ").
std::vector<double> finiteNumbers(const std::string& path, int line_no,
                                  const std::vector<std::string>& tokens, std::size_t first,
                                  const std::string& label = "");

}  // namespace omnidso::detail
