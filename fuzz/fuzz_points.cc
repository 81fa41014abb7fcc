// libFuzzer target: point files (io/point_export.h, read_points). The first input byte chooses the extension
// (even: .ply, odd: .csv); the rest is the file.
#include "fuzz/fuzz_common.h"
#include "io/point_export.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  if (size < 1) return 0;
  const char* name = (data[0] & 1) != 0 ? "points.csv" : "points.ply";
  const auto path = fuzz::write_file(name, data + 1, size - 1);
  constexpr std::size_t kMaxPoints = 100000;  // the cap itself is what is checked, at a size a fuzzer reaches
  fuzz::expect_input_error([&] {
    const Points2 points = io::read_points(path, kMaxPoints);
    fuzz::check(!points.empty() && points.size() <= kMaxPoints, "point count");
    for (const Vec2& p : points) fuzz::check(fuzz::finite(p), "point finite");
  });
  return 0;
}
