// Settings files of `partslam slam`, `loops` and `locate` (--config FILE.yaml): YAML maps whose keys are the fields
// of the config structs, a nested map for a nested struct, e.g.
//   front_end:
//     matcher:
//       sigma: 0.1
//   back_end:
//     max_rounds: 8
// A key left out keeps its default; an unknown key, a value of the wrong type or out of range is an InputError
// naming the file, the line and the field's path. config_yaml writes every field (--print-config), in a form the
// reader takes back unchanged.
#pragma once

#include <filesystem>
#include <string>

#include "core/evaluation/loop_evaluation.h"
#include "core/maps/submap.h"
#include "core/matching/localizer.h"
#include "core/slam/loop_closure.h"
#include "core/slam/slam.h"

namespace partslam::io {

/// What `partslam loops` is set by: the loop closures, which are accepted, and how they are judged (the truth's
/// min_travel_gap is the loops' and has no key of its own).
struct LoopsConfig {
  LoopClosureConfig loops;
  double min_confidence = 0.2;  ///< closures at least this confident are accepted
  LoopTruthConfig truth;
};

/// What `partslam locate` is set by: how the local map is built and how it is located.
struct LocateConfig {
  SubmapConfig submaps;
  LocalizerConfig localizer;
};

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
