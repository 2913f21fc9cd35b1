// Text helpers shared by the table writers: Markdown cells and rows, CSV fields (RFC 4180) and
// numbers, and the three-significant-digit format of the printed tables.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace hyfal::text {

inline constexpr std::string_view kMissing = "–";

// Three significant digits in fixed notation; exponent notation only at the extremes.
inline std::string format_significant(double value, int digits = 3) {
  if (std::isnan(value)) return std::string(kMissing);
  if (value == 0.0 || !std::isfinite(value)) return fmt::format("{}", value);
  const double magnitude = std::abs(value);
  if (magnitude < 1e-3 || magnitude >= 1e6) return fmt::format("{:.{}g}", value, digits);
  int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(magnitude))));
  // Rounding may carry into a new leading digit (9.996 -> 10.00); drop the extra decimal.
  if (decimals > 0 && std::round(magnitude * std::pow(10.0, decimals)) >= std::pow(10.0, digits)) --decimals;
  return fmt::format("{:.{}f}", value, decimals);
}

// Markdown has no escape for a line break inside a cell, and "|" would end the cell.
inline std::string markdown_cell(std::string_view text) {
  std::string cell;
  for (const char c : text) {
    if (c == '|')
      cell += "\\|";
    else if (c == '\n' || c == '\r')
      cell += ' ';
    else
      cell += c;
  }
  return cell;
}

inline std::string markdown_row(const std::vector<std::string>& cells) {
  return fmt::format("| {} |\n", fmt::join(cells, " | "));
}

// The separator line of a Markdown table: the first `text_columns` left-aligned, the rest right.
inline std::string markdown_separator(std::size_t text_columns, std::size_t columns) {
  std::vector<std::string> separator;
  for (std::size_t c = 0; c < columns; ++c) separator.emplace_back(c < text_columns ? "---" : "--:");
  return markdown_row(separator);
}

// Settings as "key=value, key=value"; "–" for none.
inline std::string settings_text(const std::vector<std::pair<std::string, std::string>>& settings) {
  if (settings.empty()) return std::string(kMissing);
  std::vector<std::string> parts;
  for (const auto& [key, value] : settings) parts.push_back(fmt::format("{}={}", key, value));
  return fmt::format("{}", fmt::join(parts, ", "));
}

// "- notes: ...\n" with the notes' later lines indented to stay in the list item; "" for none.
inline std::string notes_line(std::string notes) {
  while (!notes.empty() && (notes.back() == '\n' || notes.back() == ' ')) notes.pop_back();
  if (notes.empty()) return "";
  std::string indented;
  for (const char c : notes) {
    indented += c;
    if (c == '\n') indented += "  ";
  }
  return fmt::format("- notes: {}\n", indented);
}

// RFC 4180: a field with a comma, quote or line break is quoted, quotes doubled.
inline std::string csv_field(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string field = "\"";
  for (const char c : text) {
    if (c == '"') field += '"';
    field += c;
  }
  field += '"';
  return field;
}

// Full precision; an empty field for NaN.
inline std::string csv_number(double value) {
  if (std::isnan(value)) return {};
  return fmt::format("{}", value);
}

}  // namespace hyfal::text
