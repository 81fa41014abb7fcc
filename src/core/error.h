// The one exception type for bad input and bad parameters. Messages name the file, line and field
// (or the parameter) at fault; the CLI prints them and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace partslam {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Runs validate_part, the check of a config nested in another; its InputError "<part's label>: FIELD ..." is
/// thrown again as "<owner>: PATH.FIELD ...", so a nested setting is named by its path from the outer config, e.g.
/// "slam config: back_end.weights.loop_rotation must be finite and > 0, got -1".
template <class Check>
void validate_nested(const std::string& owner, const std::string& path, const Check& validate_part) {
  try {
    validate_part();
  } catch (const InputError& e) {
    std::string what = e.what();
    const std::size_t label = what.find(": ");  // the part's own label ("back end config"), replaced by the path
    if (label != std::string::npos &&
        what.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ ") == label)
      what.erase(0, label + 2);
    throw InputError(owner + ": " + path + "." + what);
  }
}

}  // namespace partslam
