#include "apps/dmm_options.h"

#include <numbers>
#include <sstream>

#include "core/error.h"

namespace partslam::apps {

void add_dmm_options(CLI::App& cmd, DmmConfig& dmm) {
  cmd.add_option("--dmm-dilation", dmm.dilation, "dMM: target dilation [cells]")->capture_default_str();
  std::ostringstream window;
  window << dmm.angular_window * kDegreesPerRadian;
  cmd.add_option_function<double>(
         "--dmm-angular-window",
         [&dmm](double deg) {
           // Checked here, in the flag's unit: the config's own check speaks of radians.
           if (!(deg >= 0.0 && deg <= 45.0))
             throw InputError("--dmm-angular-window must be in [0, 45] deg, got " + std::to_string(deg));
           dmm.angular_window = deg * std::numbers::pi / 180.0;
         },
         "dMM: residual rotation window about each rotation family [deg]")
      ->default_str(window.str());
  cmd.add_option(
         "--dmm-turns", dmm.canonical_turns,
         "dMM: rotation families searched about the canonical frame, 4 (quarter turns) or 8 (multiples of "
         "45 deg)")
      ->capture_default_str();
}

}  // namespace partslam::apps
