// Settings files of `partslam slam`, `loops` and `locate` (--config FILE.yaml): YAML maps whose keys are the fields
// of the config structs, a nested map for a nested struct, e.g.
//   front_end:
//     matcher:
//       sigma: 0.1
//   back_end:
//     max_rounds: 8
// A key left out keeps its default; an unknown key, a value of the wrong type or out of range is an InputError
// naming the file, the line and the field's path. config_yaml writes every field (--print-config), in a form the
// reader takes back unchanged. The fields are those of the tables in io/formats/config_fields.h.
#pragma once

#include <filesystem>
#include <string>

#include "io/formats/config_fields.h"

namespace partslam::io {

/// Throw InputError naming the field by its path ("loops config: loops.other_place must be ...").
void validate(const LoopsConfig& config);
void validate(const LocateConfig& config);

/// Reads `file` over `config` (the fields it names replace those of `config`), then validates the result. Throws
/// InputError "<file>: ..." for an unreadable file, invalid YAML, an unknown key, a value of the wrong type, or a
/// value out of range.
void read_config_file(const std::filesystem::path& file, SlamConfig& config);
void read_config_file(const std::filesystem::path& file, LoopsConfig& config);
void read_config_file(const std::filesystem::path& file, LocateConfig& config);

/// Every field of `config` as YAML that read_config_file reads back to the same values.
std::string config_yaml(const SlamConfig& config);
std::string config_yaml(const LoopsConfig& config);
std::string config_yaml(const LocateConfig& config);

}  // namespace partslam::io
