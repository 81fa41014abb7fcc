#include "io/formats/point_export.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "io/files/atomic_file.h"

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

namespace {

// One point file read line by line: its points, laser origins and pose, with the line each error names.
class PointFileReader {
 public:
  PointFileReader(const std::filesystem::path& path, std::size_t max_points, std::ifstream& in)
      : path_(path), max_points_(max_points), in_(in) {}

  PointFile read_csv() {
    bool header_possible = true;  // the first line that is not a comment may be a header
    while (std::getline(in_, text_)) {
      ++line_;
      if (!text_.empty() && text_.back() == '\r') text_.pop_back();
      if (!text_.empty() && text_[0] == '#') {
        const std::vector<std::string> f = split(text_.substr(1), ' ');
        read_pose(f, 0);
        read_origin(f);
        continue;
      }
      if (text_.empty()) continue;
      const std::vector<std::string> f = split(text_, ',');
      if (f.size() < 2) fail(path_, line_, "expected x,y");
      double v = 0;
      const bool first = header_possible;
      header_possible = false;
      if (first && std::from_chars(f[0].data(), f[0].data() + f[0].size(), v).ec != std::errc()) continue;  // header
      add(file_.points, number(path_, line_, f[0], "x"), number(path_, line_, f[1], "y"), "points");
    }
    return std::move(file_);
  }

  PointFile read_ply() {
    std::getline(in_, text_), ++line_;
    if (text_.rfind("ply", 0) != 0) fail(path_, line_, "not a PLY file (no 'ply' magic)");
    const std::vector<Element> elements = read_ply_header();
    const auto vertex =
        std::find_if(elements.begin(), elements.end(), [](const Element& e) { return e.name == "vertex"; });
    if (vertex == elements.end() || vertex->x_column < 0 || vertex->y_column < 0)
      fail(path_, line_, "PLY header lacks a vertex element with x and y");
    for (const Element& e : elements) read_ply_rows(e);
    return std::move(file_);
  }

 private:
  // A PLY element: the elements come in header order (their rows too, one line each): the vertices are the
  // points, "laser_origin" the laser's positions, any other element is skipped.
  struct Element {
    std::string name;
    long count = 0;
    int x_column = -1, y_column = -1, columns = 0;
  };

  std::vector<Element> read_ply_header() {
    std::vector<Element> elements;
    for (;;) {
      if (!std::getline(in_, text_)) fail(path_, line_, "truncated PLY header (no end_header)");
      ++line_;
      const std::vector<std::string> f = split(text_, ' ');
      if (!f.empty() && f[0] == "comment") read_pose(f, 1);
      if (f.empty() || f[0] == "comment" || f[0] == "obj_info") continue;
      if (f[0] == "end_header") return elements;
      if (f[0] == "format" && (f.size() < 2 || f[1] != "ascii"))
        fail(path_, line_, "only ASCII PLY is read (this one is '" + (f.size() > 1 ? f[1] : std::string()) + "')");
      if (f[0] == "element") {
        if (f.size() != 3) fail(path_, line_, "expected 'element NAME COUNT'");
        const std::string field = "element " + f[1];
        elements.push_back({f[1], count(path_, line_, f[2], field.c_str())});
      } else if (f[0] == "property" && !elements.empty()) {
        Element& e = elements.back();
        if (f.back() == "x") e.x_column = e.columns;
        if (f.back() == "y") e.y_column = e.columns;
        ++e.columns;
      }
    }
  }

  void read_ply_rows(const Element& e) {
    Points2* to = e.name == "vertex" ? &file_.points : e.name == kOriginKey ? &file_.laser_origins : nullptr;
    if (to && (e.x_column < 0 || e.y_column < 0)) fail(path_, line_, "PLY element " + e.name + " lacks x or y");
    if (to && static_cast<unsigned long>(e.count) > max_points_)
      fail(path_, line_,
           std::to_string(e.count) + (to == &file_.points ? " vertices" : " laser origins") + " is more than " +
               std::to_string(max_points_));
    for (long k = 0; k < e.count; ++k) {
      if (!std::getline(in_, text_))
        fail(path_, line_,
             "truncated: " + std::to_string(k) + " of " + std::to_string(e.count) + " " +
                 (e.name == "vertex" ? std::string("vertices") : e.name + " rows"));
      ++line_;
      if (!to) continue;
      const std::vector<std::string> f = split(text_, ' ');
      if (static_cast<int>(f.size()) < e.columns)
        fail(path_, line_, "expected " + std::to_string(e.columns) + " values");
      to->emplace_back(number(path_, line_, f[static_cast<std::size_t>(e.x_column)], "x"),
                       number(path_, line_, f[static_cast<std::size_t>(e.y_column)], "y"));
    }
  }

  // "T_world_points x y theta" in a comment (write_points): the pose of the points' frame in the world frame.
  void read_pose(const std::vector<std::string>& f, std::size_t at) {
    if (f.size() <= at || f[at] != kPoseKey) return;
    if (f.size() != at + 4) fail(path_, line_, std::string(kPoseKey) + ": expected x y theta");
    if (file_.T_world_points) fail(path_, line_, std::string(kPoseKey) + ": given twice");
    file_.T_world_points = Pose2{number(path_, line_, f[at + 1], "T_world_points x"),
                                 number(path_, line_, f[at + 2], "T_world_points y"),
                                 number(path_, line_, f[at + 3], "T_world_points theta")};
  }

  // "laser_origin x y" in a comment (write_points): one of the laser's positions, in the points' frame.
  void read_origin(const std::vector<std::string>& f) {
    if (f.empty() || f[0] != kOriginKey) return;
    if (f.size() != 3) fail(path_, line_, std::string(kOriginKey) + ": expected x y");
    add(file_.laser_origins, number(path_, line_, f[1], "laser_origin x"),
        number(path_, line_, f[2], "laser_origin y"), "laser origins");
  }

  void add(Points2& to, double x, double y, const char* what) {
    if (to.size() == max_points_) fail(path_, line_, "more than " + std::to_string(max_points_) + " " + what);
    to.emplace_back(x, y);
  }

  const std::filesystem::path& path_;
  const std::size_t max_points_;
  std::ifstream& in_;
  std::string text_;
  std::size_t line_ = 0;
  PointFile file_;
};

}  // namespace

PointFile read_point_file(const std::filesystem::path& path, std::size_t max_points) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open the point file");
  const std::string ext = path.extension().string();
  if (ext != ".ply" && ext != ".csv")
    throw InputError(path.string() + ": unknown point file type '" + ext + "' (expected .ply or .csv)");
  PointFileReader reader(path, max_points, in);
  PointFile file = ext == ".csv" ? reader.read_csv() : reader.read_ply();
  if (file.points.empty()) throw InputError(path.string() + ": no points");
  return file;
}

}  // namespace partslam::io
