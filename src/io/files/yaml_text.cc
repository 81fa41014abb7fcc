#include "io/files/yaml_text.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>

namespace partslam::io {

bool holds_binary_data(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char head[4096];
  in.read(head, sizeof head);
  const std::string_view start(head, static_cast<std::size_t>(in.gcount()));
  // A PNG, or a binary PGM (whose first rows may all be one grey above the control bytes).
  if (start.starts_with("\x89PNG") ||
      (start.size() > 2 && start.starts_with("P5") && std::isspace(static_cast<unsigned char>(start[2]))))
    return true;
  return std::ranges::any_of(start, [](const char ch) {
    const auto c = static_cast<unsigned char>(ch);
    return c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f';
  });
}

std::string yaml_double_quoted(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (u < 0x20 || u == 0x7f) {
      char escaped[5];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", u);
      quoted += escaped;
    } else {
      quoted += c;
    }
  }
  return quoted + '"';
}

}  // namespace partslam::io
