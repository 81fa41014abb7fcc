#include "io/logs/log_read_options.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace partslam::io {

void validate(const LogReadOptions& options) {
  if (options.max_points < 1) throw InputError("LogReadOptions.max_points: must be >= 1");
  if (!std::isfinite(options.min_range) || options.min_range < 0.0) {
    throw InputError("LogReadOptions.min_range: must be finite and >= 0, got " +
                     std::to_string(options.min_range));
  }
  if (std::isnan(options.max_usable_range) || options.max_usable_range <= options.min_range) {
    throw InputError("LogReadOptions.max_usable_range: must exceed min_range, got " +
                     std::to_string(options.max_usable_range));
  }
  if (std::isnan(options.no_return_range) || options.no_return_range <= options.min_range) {
    throw InputError("LogReadOptions.no_return_range: must exceed min_range, got " +
                     std::to_string(options.no_return_range));
  }
  if (!(options.no_return_code_share >= 0.0 && options.no_return_code_share <= 1.0)) {
    throw InputError("LogReadOptions.no_return_code_share: must be in [0, 1], got " +
                     std::to_string(options.no_return_code_share));
  }
  if (!std::isfinite(options.no_return_code_min_range) || options.no_return_code_min_range < 0.0) {
    throw InputError("LogReadOptions.no_return_code_min_range: must be finite and >= 0, got " +
                     std::to_string(options.no_return_code_min_range));
  }
  if (!(options.max_scan_jump > 0.0)) {
    throw InputError("LogReadOptions.max_scan_jump: must be positive, got " + std::to_string(options.max_scan_jump));
  }
  switch (options.flaser_spacing) {
    case FlaserSpacing::kCarmen:
    case FlaserSpacing::kPiOverN:
    case FlaserSpacing::kPiOverNMinus1:
      return;
  }
  throw InputError("LogReadOptions.flaser_spacing: unknown value");
}

}  // namespace partslam::io
