#pragma once
// A number written as text, all of it: std::stod reads a prefix ("1.5x" → 1.5) and throws on
// none, so every reader of numbers in text files and options checks how much it used. One
// place for that check; each caller says in its own words what was expected.

#include <cstddef>
#include <exception>
#include <optional>
#include <string>

namespace omnidso {

// The value of `text` when the whole of it is a number (infinities and NaN included: callers
// that need a finite value check); nullopt otherwise.
inline std::optional<double> parseWholeNumber(const std::string& text) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size()) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

}  // namespace omnidso
