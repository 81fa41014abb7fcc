// libFuzzer target: point files (io/formats/point_export.h, read_point_file: points, the frame's pose, laser
// origins). The first input byte chooses the extension (even: .ply, odd: .csv); the rest is the file.
#include "fuzz/fuzz_common.h"
#include "io/formats/point_export.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  if (size < 1) return 0;
  const char* name = (data[0] & 1) != 0 ? "points.csv" : "points.ply";
  const auto path = fuzz::write_file(name, data + 1, size - 1);
  constexpr std::size_t kMaxPoints = 100000;  // the cap itself is what is checked, at a size a fuzzer reaches
  fuzz::expect_input_error([&] {
    const io::PointFile file = io::read_point_file(path, kMaxPoints);
    fuzz::check(!file.points.empty() && file.points.size() <= kMaxPoints, "point count");
    for (const Vec2& p : file.points) fuzz::check(fuzz::finite(p), "point finite");
    fuzz::check(file.laser_origins.size() <= kMaxPoints, "laser origin count");
    for (const Vec2& o : file.laser_origins) fuzz::check(fuzz::finite(o), "laser origin finite");
    if (file.T_world_points) fuzz::check(fuzz::finite(*file.T_world_points), "pose finite");
  });
  return 0;
}
