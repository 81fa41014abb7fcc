#include "apps/config_options.h"

#include <iostream>

namespace partslam::apps {

void add_config_options(CLI::App& cmd, std::string& file, std::function<std::string()> defaults_yaml) {
  cmd.add_option("--config", file,
                 "a YAML settings file (keys: the fields of the settings, nested maps for nested ones; see "
                 "--print-config); flags given override it");
  cmd.add_flag_callback(
         "--print-config",
         [yaml = std::move(defaults_yaml)] {
           std::cout << yaml();
           throw CLI::Success();
         },
         "write every setting with its default as YAML (a file --config reads) and exit")
      ->trigger_on_parse();
}

}  // namespace partslam::apps
