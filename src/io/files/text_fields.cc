#include "io/files/text_fields.h"

#include <charconv>
#include <cmath>
#include <string>
#include <system_error>

namespace partslam::io {
namespace {

/// The token for a message, quoted and cut to a readable length.
std::string quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  if (token.size() <= kMaxShown) return "'" + std::string(token) + "'";
  return "'" + std::string(token.substr(0, kMaxShown)) + "...'";
}

}  // namespace

void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  const char* p = line.data();
  const char* const end = p + line.size();
  while (p != end) {
    while (p != end && (*p == ' ' || *p == '\t')) ++p;
    const char* start = p;
    while (p != end && *p != ' ' && *p != '\t') ++p;
    if (p != start) out.emplace_back(start, static_cast<std::size_t>(p - start));
  }
}

void fail_field(const LineReader& reader, const FieldName& field, std::string_view problem) {
  std::string name(field.message);
  if (!field.field.empty()) {
    if (!name.empty()) name += ' ';
    name += field.field;
  }
  if (field.index >= 0) name += "[" + std::to_string(field.index) + "]";
  reader.fail(name + ": " + std::string(problem));
}

double parse_number(const LineReader& reader, std::string_view token, const FieldName& field) {
  const char* begin = token.data();
  const char* const end = begin + token.size();
  if (begin != end && *begin == '+') ++begin;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec == std::errc::result_out_of_range) fail_field(reader, field, "number out of range " + quoted(token));
  if (ec != std::errc() || ptr != end || begin == end) {
    fail_field(reader, field, "not a number " + quoted(token));
  }
  if (!std::isfinite(value)) fail_field(reader, field, "not a finite number " + quoted(token));
  return value;
}

long parse_count(const LineReader& reader, std::string_view token, const FieldName& field, long max_value) {
  long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size() || token.empty()) {
    fail_field(reader, field, "not a whole number " + quoted(token));
  }
  if (value < 0 || value > max_value) {
    fail_field(reader, field,
               "out of range " + quoted(token) + " (allowed 0.." + std::to_string(max_value) + ")");
  }
  return value;
}

}  // namespace partslam::io
