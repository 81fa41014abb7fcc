// Text that the YAML files PartSLAM writes (settings files, map_server map.yaml) carry as strings.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace partslam::io {

/// `text` as a YAML double-quoted scalar that reads back to the same bytes: '"' and '\' escaped, every control
/// character (and DEL) as \xNN; other bytes as they are. A plain scalar would not do for every text: a file name
/// "map: 2.pgm" or "#1.pgm" reads as a map or a comment, and a raw line break inside quotes as a space.
std::string yaml_double_quoted(std::string_view text);

/// Whether the file at path holds binary data (a PNG or binary PGM signature, or a NUL or a control byte other than
/// tab, line feed, carriage return and form feed in its first 4 KiB): an image or a log given where a YAML file is
/// read. False when it cannot be
/// read (the YAML reader says why).
bool holds_binary_data(const std::filesystem::path& path);

}  // namespace partslam::io
