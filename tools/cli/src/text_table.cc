#include <fmt/core.h>

#include <omnidso/cli/text_table.hpp>
#include <omnidso/core/error.hpp>
#include <sstream>

namespace omnidso::cli {
namespace {

void checkShape(const TextTable& table) {
  for (size_t r = 0; r < table.rows.size(); ++r)
    if (table.rows[r].size() != table.header.size())
      throw Error(fmt::format("table row {} has {} cells, the header {}", r, table.rows[r].size(),
                              table.header.size()));
}

std::string escapeMarkdown(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out;
}

// Display width: UTF-8 continuation bytes take no column.
size_t displayWidth(const std::string& text) {
  size_t width = 0;
  for (unsigned char c : text) width += (c & 0xC0) != 0x80;
  return width;
}

std::string pad(const std::string& text, size_t width, bool left) {
  const std::string fill(width - std::min(width, displayWidth(text)), ' ');
  return left ? text + fill : fill + text;
}

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

std::string markdownTable(const TextTable& table) {
  checkShape(table);
  std::vector<std::vector<std::string>> cells{table.header};
  for (const auto& row : table.rows) cells.push_back(row);
  std::vector<size_t> widths(table.header.size(), 3);
  for (auto& row : cells)
    for (size_t c = 0; c < row.size(); ++c) {
      row[c] = escapeMarkdown(row[c]);
      widths[c] = std::max(widths[c], displayWidth(row[c]));
    }
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& row) {
    out << "|";
    for (size_t c = 0; c < row.size(); ++c)
      out << " " << pad(row[c], widths[c], c < table.label_columns) << " |";
    out << "\n";
  };
  line(cells[0]);
  out << "|";
  for (size_t c = 0; c < widths.size(); ++c)
    out << (c < table.label_columns ? " :" + std::string(widths[c] - 1, '-')
                                    : " " + std::string(widths[c] - 1, '-') + ":")
        << " |";
  out << "\n";
  for (size_t r = 1; r < cells.size(); ++r) line(cells[r]);
  return out.str();
}

std::string csvTable(const TextTable& table) {
  checkShape(table);
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& row) {
    for (size_t c = 0; c < row.size(); ++c) out << (c ? "," : "") << csvField(row[c]);
    out << "\n";
  };
  line(table.header);
  for (const auto& row : table.rows) line(row);
  return out.str();
}

}  // namespace omnidso::cli
