// The text calibration readers' tokens and numbers (calibration_text.hpp).
#include "calibration_text.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "omnidso/core/error.hpp"
#include "omnidso/core/number_text.hpp"

namespace omnidso::detail {

std::vector<std::string> textTokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

std::vector<double> finiteNumbers(const std::string& path, int line_no,
                                  const std::vector<std::string>& tokens, std::size_t first,
                                  const std::string& label) {
  std::vector<double> out;
  for (std::size_t i = first; i < tokens.size(); ++i) {
    const std::optional<double> x = parseWholeNumber(tokens[i]);
    if (!x) throw fileError(path, line_no, label + "'" + tokens[i] + "' is not a number");
    if (!std::isfinite(*x))
      throw fileError(path, line_no, label + "'" + tokens[i] + "' is not finite");
    out.push_back(*x);
  }
  return out;
}

}  // namespace omnidso::detail
