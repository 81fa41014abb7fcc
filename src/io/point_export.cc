#include "io/point_export.h"

#include <iomanip>

#include "core/error.h"
#include "io/atomic_file.h"

namespace partslam::io {

PointFormat parse_point_format(const std::string& name) {
  if (name == "ply") return PointFormat::kPly;
  if (name == "csv") return PointFormat::kCsv;
  throw InputError("--format: expected ply or csv, got '" + name + "'");
}

void write_points(const std::filesystem::path& path, const Points2& points, PointFormat format) {
  write_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(6) << std::fixed;
    if (format == PointFormat::kPly) {
      out << "ply\nformat ascii 1.0\ncomment PartSLAM map points [m]\nelement vertex " << points.size()
          << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
      for (const Vec2& p : points) out << p.x() << ' ' << p.y() << " 0\n";
    } else {
      out << "x,y\n";
      for (const Vec2& p : points) out << p.x() << ',' << p.y() << '\n';
    }
  });
}

}  // namespace partslam::io
