// libFuzzer target: relation files of the Freiburg benchmark (io/logs/relations.h), the input being the whole file.
#include "fuzz/fuzz_common.h"
#include "io/logs/relations.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  const auto path = fuzz::write_file("log.relations", data, size);
  fuzz::expect_input_error([&] {
    const io::Relations relations = io::read_relations(path);
    fuzz::check(!relations.empty(), "relations not empty");
    for (const io::Relation& r : relations) {
      fuzz::check(std::isfinite(r.t1) && std::isfinite(r.t2) && fuzz::finite(r.T_1_2), "relation finite");
      fuzz::check(std::abs(r.T_1_2.theta) <= 3.1415927, "relation yaw wrapped");
    }
  });
  return 0;
}
