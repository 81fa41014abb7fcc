#include "io/point_export.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/atomic_file.h"

namespace partslam::io {

namespace {
constexpr const char* kPoseKey = "T_world_points";
constexpr const char* kOriginKey = "laser_origin";
}  // namespace

PointFormat parse_point_format(const std::string& name) {
  if (name == "ply") return PointFormat::kPly;
  if (name == "csv") return PointFormat::kCsv;
  throw InputError("point format: expected ply or csv, got '" + name + "'");
}

void write_points(const std::filesystem::path& path, const Points2& points, PointFormat format,
                  const std::optional<Pose2>& T_world_points, const Points2& laser_origins) {
  write_atomically(path, [&](std::ostream& out) {
    // The pose with every digit a double holds: reading it back must put the points on the same grid cells.
    const auto pose = [&](const char* prefix) {
      if (!T_world_points) return;
      out << std::setprecision(17) << std::defaultfloat << prefix << " " << kPoseKey << " " << T_world_points->x << ' '
          << T_world_points->y << ' ' << T_world_points->theta << "\n";
    };
    if (format == PointFormat::kPly) {
      out << "ply\nformat ascii 1.0\ncomment PartSLAM map points [m]\n";
      pose("comment");
      out << "element vertex " << points.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
      if (!laser_origins.empty())
        out << "element " << kOriginKey << " " << laser_origins.size()
            << "\nproperty float x\nproperty float y\n";
      out << "end_header\n";
      out << std::setprecision(6) << std::fixed;
      for (const Vec2& p : points) out << p.x() << ' ' << p.y() << " 0\n";
      for (const Vec2& o : laser_origins) out << o.x() << ' ' << o.y() << "\n";
    } else {
      pose("#");
      out << std::setprecision(6) << std::fixed;
      for (const Vec2& o : laser_origins) out << "# " << kOriginKey << " " << o.x() << ' ' << o.y() << "\n";
      out << "x,y\n";
      for (const Vec2& p : points) out << p.x() << ',' << p.y() << '\n';
    }
  });
}

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, std::size_t line, const std::string& what) {
  throw InputError(path.string() + ":" + std::to_string(line) + ": " + what);
}

double number(const std::filesystem::path& path, std::size_t line, const std::string& token, const char* field) {
  double v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size())
    fail(path, line, std::string(field) + ": not a number: '" + token.substr(0, 40) + "'");
  if (!std::isfinite(v)) fail(path, line, std::string(field) + ": not finite: '" + token + "'");
  return v;
}

// A whole number >= 0 (an element count); anything else, or one beyond 2^62, is refused.
long count(const std::filesystem::path& path, std::size_t line, const std::string& token, const char* field) {
  long v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size() || v < 0 || v > (1L << 62))
    fail(path, line, std::string(field) + ": not a whole number >= 0: '" + token.substr(0, 40) + "'");
  return v;
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::string token;
  std::istringstream in(text);
  if (separator == ' ') {
    while (in >> token) out.push_back(token);
  } else {
    while (std::getline(in, token, separator)) {
      const auto b = token.find_first_not_of(" \t\r"), e = token.find_last_not_of(" \t\r");
      out.push_back(b == std::string::npos ? "" : token.substr(b, e - b + 1));
    }
  }
  return out;
}

}  // namespace

Points2 read_points(const std::filesystem::path& path, std::size_t max_points) {
  return read_point_file(path, max_points).points;
}

PointFile read_point_file(const std::filesystem::path& path, std::size_t max_points) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the point file");
  const std::string ext = path.extension().string();
  if (ext != ".ply" && ext != ".csv")
    throw InputError(path.string() + ": unknown point file type '" + ext + "' (expected .ply or .csv)");
  PointFile file;
  Points2& points = file.points;
  std::string text;
  std::size_t line = 0;
  // "T_world_points x y theta" in a comment (write_points): the pose of the points' frame in the world frame.
  const auto read_pose = [&](const std::vector<std::string>& f, std::size_t at) {
    if (f.size() <= at || f[at] != kPoseKey) return;
    if (f.size() != at + 4) fail(path, line, std::string(kPoseKey) + ": expected x y theta");
    if (file.T_world_points) fail(path, line, std::string(kPoseKey) + ": given twice");
    file.T_world_points = Pose2{number(path, line, f[at + 1], "T_world_points x"),
                                number(path, line, f[at + 2], "T_world_points y"),
                                number(path, line, f[at + 3], "T_world_points theta")};
  };
  bool header_possible = true;  // the first line that is not a comment may be a header
  const auto add = [&](Points2& to, double x, double y, const char* what) {
    if (to.size() == max_points) fail(path, line, "more than " + std::to_string(max_points) + " " + what);
    to.emplace_back(x, y);
  };
  // "laser_origin x y" in a comment (write_points): one of the laser's positions, in the points' frame.
  const auto read_origin = [&](const std::vector<std::string>& f) {
    if (f.empty() || f[0] != kOriginKey) return;
    if (f.size() != 3) fail(path, line, std::string(kOriginKey) + ": expected x y");
    add(file.laser_origins, number(path, line, f[1], "laser_origin x"),
        number(path, line, f[2], "laser_origin y"), "laser origins");
  };
  if (ext == ".csv") {
    while (std::getline(in, text)) {
      ++line;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      if (!text.empty() && text[0] == '#') {
        const std::vector<std::string> f = split(text.substr(1), ' ');
        read_pose(f, 0);
        read_origin(f);
        continue;
      }
      if (text.empty()) continue;
      const std::vector<std::string> f = split(text, ',');
      if (f.size() < 2) fail(path, line, "expected x,y");
      double v = 0;
      const bool first = header_possible;
      header_possible = false;
      if (first && std::from_chars(f[0].data(), f[0].data() + f[0].size(), v).ec != std::errc()) continue;  // header
      add(points, number(path, line, f[0], "x"), number(path, line, f[1], "y"), "points");
    }
  } else {
    std::getline(in, text), ++line;
    if (text.rfind("ply", 0) != 0) fail(path, line, "not a PLY file (no 'ply' magic)");
    // The elements in header order (their rows come in that order, one line each): the vertices are the
    // points, "laser_origin" the laser's positions, any other element is skipped.
    struct Element {
      std::string name;
      long count = 0;
      int x_column = -1, y_column = -1, columns = 0;
    };
    std::vector<Element> elements;
    for (;;) {
      if (!std::getline(in, text)) fail(path, line, "truncated PLY header (no end_header)");
      ++line;
      const std::vector<std::string> f = split(text, ' ');
      if (!f.empty() && f[0] == "comment") read_pose(f, 1);
      if (f.empty() || f[0] == "comment" || f[0] == "obj_info") continue;
      if (f[0] == "end_header") break;
      if (f[0] == "format" && (f.size() < 2 || f[1] != "ascii"))
        fail(path, line, "only ASCII PLY is read (this one is '" + (f.size() > 1 ? f[1] : std::string()) + "')");
      if (f[0] == "element") {
        if (f.size() != 3) fail(path, line, "expected 'element NAME COUNT'");
        const std::string field = "element " + f[1];
        elements.push_back({f[1], count(path, line, f[2], field.c_str())});
      } else if (f[0] == "property" && !elements.empty()) {
        Element& e = elements.back();
        if (f.back() == "x") e.x_column = e.columns;
        if (f.back() == "y") e.y_column = e.columns;
        ++e.columns;
      }
    }
    const auto vertex =
        std::find_if(elements.begin(), elements.end(), [](const Element& e) { return e.name == "vertex"; });
    if (vertex == elements.end() || vertex->x_column < 0 || vertex->y_column < 0)
      fail(path, line, "PLY header lacks a vertex element with x and y");
    for (const Element& e : elements) {
      Points2* to = e.name == "vertex" ? &points : e.name == kOriginKey ? &file.laser_origins : nullptr;
      if (to && (e.x_column < 0 || e.y_column < 0))
        fail(path, line, "PLY element " + e.name + " lacks x or y");
      if (to && static_cast<unsigned long>(e.count) > max_points)
        fail(path, line,
             std::to_string(e.count) + (to == &points ? " vertices" : " laser origins") + " is more than " +
                 std::to_string(max_points));
      for (long k = 0; k < e.count; ++k) {
        if (!std::getline(in, text))
          fail(path, line,
               "truncated: " + std::to_string(k) + " of " + std::to_string(e.count) + " " +
                   (e.name == "vertex" ? std::string("vertices") : e.name + " rows"));
        ++line;
        if (!to) continue;
        const std::vector<std::string> f = split(text, ' ');
        if (static_cast<int>(f.size()) < e.columns)
          fail(path, line, "expected " + std::to_string(e.columns) + " values");
        to->emplace_back(number(path, line, f[static_cast<std::size_t>(e.x_column)], "x"),
                         number(path, line, f[static_cast<std::size_t>(e.y_column)], "y"));
      }
    }
  }
  if (points.empty()) throw InputError(path.string() + ": no points");
  return file;
}

}  // namespace partslam::io
