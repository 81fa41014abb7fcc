// How the CLI writes JSON (--json of info, eval, demo, loops, slam): indented, and never failing on text that
// is not UTF-8 (a log's file name, a name stored by an older version): such bytes become U+FFFD rather than
// losing the whole output after the work is done. A pose is written as {"x", "y", "theta"} everywhere.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/types.h"

namespace partslam::apps {

inline std::string json_text(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

inline nlohmann::json pose_json(const Pose2& p) { return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}}; }

}  // namespace partslam::apps
