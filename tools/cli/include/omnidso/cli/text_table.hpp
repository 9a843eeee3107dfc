#pragma once
// A table of text cells written as a Markdown (GitHub) table or as CSV (RFC 4180 quoting).

#include <string>
#include <vector>

namespace omnidso::cli {

struct TextTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each as long as the header
  size_t label_columns = 1;  // Markdown: these first columns left-aligned, the others right
};

// Columns padded to equal width, aligned as label_columns says; '|' in
// cells escaped. Throws omnidso::Error for a row whose length differs from the header's.
std::string markdownTable(const TextTable& table);

// Fields with a comma, quote or line break are quoted, quotes doubled; lines end in "\n".
std::string csvTable(const TextTable& table);

}  // namespace omnidso::cli
