// The one exception type for bad input and bad parameters. Messages name the file, line and field
// (or the parameter) at fault; the CLI prints them and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

namespace partslam {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace partslam
