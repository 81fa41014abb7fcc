// libFuzzer target: the settings files of `slam`, `loops` and `locate` (--config FILE.yaml,
// io/formats/config_file.h). Byte 0 picks the command (modulo 3), the rest is the file. A file that reads must
// round-trip as --print-config promises: config_yaml of what it set reads back (no InputError) to the same YAML text.
#include "fuzz/fuzz_common.h"
#include "io/formats/config_file.h"

namespace {

template <typename Config>
void read_and_round_trip(const std::filesystem::path& path) {
  using namespace partslam;
  Config config;
  if (!fuzz::expect_input_error([&] { io::read_config_file(path, config); })) return;
  const std::string yaml = io::config_yaml(config);
  Config again;
  io::read_config_file(fuzz::write_file("printed.yaml", yaml), again);  // an InputError here is a finding
  fuzz::check(io::config_yaml(again) == yaml, "config_yaml reads back to the same settings");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto path = partslam::fuzz::write_file("settings.yaml", data + 1, size - 1);
  switch (data[0] % 3) {
    case 0:
      read_and_round_trip<partslam::SlamConfig>(path);
      break;
    case 1:
      read_and_round_trip<partslam::io::LoopsConfig>(path);
      break;
    default:
      read_and_round_trip<partslam::io::LocateConfig>(path);
  }
  return 0;
}
