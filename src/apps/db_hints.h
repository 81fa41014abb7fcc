// The command line's words for what a map database lacks: the io library's errors say what is missing; these
// add the partslam command that lists or produces it.
#pragma once

#include <string>
#include <utility>

#include "core/error.h"

namespace partslam::apps {

/// f(), with `hint` added to an InputError it throws.
template <typename F>
auto with_hint(F&& f, const std::string& hint) {
  try {
    return std::forward<F>(f)();
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (" + hint + ")");
  }
}

/// Lists the map ids of a database.
inline std::string info_hint(const std::string& db) { return "'partslam info " + db + "' lists the map ids"; }

/// Stores descriptors of a database's maps.
inline std::string describe_hint(const std::string& db) {
  return "'partslam describe " + db + " --dict NAME --k K' stores K-part descriptors, --parts P the hMM query list";
}

}  // namespace partslam::apps
