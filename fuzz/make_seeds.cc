// Writes the seed corpus of every fuzz target (fuzz/run.sh calls it at `make fuzz` time; nothing of it is committed):
// small files cut from the real data (the first lines of CARMEN logs and relation files, small databases, bags,
// map_server maps and point files made from the first scans of a log, each command's default settings) plus
// synthetic ones where there is none.
// Usage: make_fuzz_seeds SHARED_DATA_DIR OUT_DIR   (OUT_DIR/<target>/...; a missing SHARED_DATA_DIR gives the
// synthetic seeds only).
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/maps/submap.h"
#include "fuzz/fuzz_map_database.h"
#include "io/logs/carmen_log.h"
#include "io/formats/config_file.h"
#include "io/files/line_reader.h"
#include "io/formats/map_server.h"
#include "io/logs/mcap_file.h"
#include "io/formats/point_export.h"
#include "io/logs/ros_bag_messages.h"
#include "io/files/sqlite.h"

namespace fs = std::filesystem;
using namespace partslam;

namespace {

fs::path out_root;
fs::path shared;
int written = 0;

void put(const std::string& target, const std::string& name, const std::string& bytes) {
  const fs::path dir = out_root / target;
  fs::create_directories(dir);
  std::ofstream(dir / name, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ++written;
}

std::string slurp(const fs::path& path, std::size_t max_bytes = std::string::npos) {
  std::ifstream in(path, std::ios::binary);
  std::string s((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return s.substr(0, max_bytes);
}

// The first lines of a text file (plain or gzip), at most max_bytes in all.
std::string head_lines(const fs::path& path, std::size_t lines, std::size_t max_bytes = 24000) {
  io::LineReader reader(path);
  std::string out;
  std::string_view line;
  for (std::size_t n = 0; n < lines && reader.next(line) && out.size() + line.size() < max_bytes; ++n) {
    out.append(line).push_back('\n');
  }
  return out;
}

std::string gzip(const std::string& text) {
  std::vector<unsigned char> out(compressBound(static_cast<uLong>(text.size())) + 32);
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = out.data();
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  deflateEnd(&z);
  return std::string(reinterpret_cast<const char*>(out.data()), z.total_out);
}

bool have(const fs::path& relative) { return fs::is_regular_file(shared / relative); }

// The first scans of a log, read to at most max_scans.
Scans first_scans(const fs::path& relative, std::size_t max_scans) {
  io::CarmenReader reader(shared / relative);
  Scans scans;
  while (scans.size() < max_scans) {
    std::optional<Scan> s = reader.next();
    if (!s) break;
    scans.push_back(std::move(*s));
  }
  return scans;
}

// Points of a few scans in the world frame, thinned to about n.
Points2 some_points(const Scans& scans, std::size_t n) {
  Points2 all;
  for (const Scan& s : scans) {
    const Points2 p = points_world(s, 8.0);
    all.insert(all.end(), p.begin(), p.end());
  }
  Points2 out;
  const std::size_t step = std::max<std::size_t>(1, all.size() / n);
  for (std::size_t i = 0; i < all.size() && out.size() < n; i += step) out.push_back(all[i]);
  return out;
}

void text_seeds() {
  const char* const logs[] = {"fr079/fr079-corrected.log.gz", "intel/intel.clf.gz", "intel/intel-robotlaser.log.gz",
                              "aces/aces.clf.gz", "corrected/orebro-corrected.log.gz",
                              "corrected/freiburg-campus-corrected.log.gz"};
  for (const char* log : logs) {
    if (!have(log)) continue;
    const std::string name = fs::path(log).filename().string();
    const std::string text = head_lines(shared / log, 14);
    put("fuzz_carmen", name + ".head", text);
    put("fuzz_gzip", name + ".text", "\x01" + text.substr(0, 8000));        // compressed by the target
    put("fuzz_gzip", name + ".gz", std::string(1, '\0') + gzip(text));     // a whole gzip stream
    put("fuzz_gzip", name + ".cut", std::string(1, '\0') + slurp(shared / log, 6000));  // a real .gz cut short
  }
  for (const char* rel : {"fr079/fr079.relations", "intel/intel.relations", "aces/aces.relations"}) {
    if (!have(rel)) continue;
    const std::string name = fs::path(rel).filename().string();
    const std::string text = head_lines(shared / rel, 40);
    put("fuzz_relations", name + ".head", text);
    put("fuzz_gzip", name + ".gz", std::string(1, '\0') + gzip(text));
  }
}

void database_seeds(const Scans& scans) {
  const fs::path tmp = out_root / "tmp.db";
  const auto make = [&](const std::string& name, std::vector<Points2> maps, Points2 dict, int page, bool v1) {
    fs::remove(tmp);
    fuzz::make_small_database(tmp, std::move(maps), std::move(dict), page, v1);
    put("fuzz_map_database", name, slurp(tmp));
    fs::remove(tmp);
  };
  make("synthetic-512.db", {}, {}, 512, false);
  make("synthetic-v1-512.db", {}, {}, 512, true);
  make("synthetic-1024.db", {}, {}, 1024, false);
  if (scans.size() >= 12) {
    std::vector<Points2> maps;
    for (std::size_t i = 0; i < 3; ++i) {
      const Scans part(scans.begin() + static_cast<long>(4 * i), scans.begin() + static_cast<long>(4 * i + 4));
      maps.push_back(some_points(part, 24));
    }
    make("fr079-512.db", maps, some_points(scans, 40), 512, false);
    make("fr079-v1-512.db", maps, some_points(scans, 40), 512, true);
  }
  // Edit scripts for fuzz_map_database_values: any bytes decode to edits.
  std::mt19937 rng(11);
  for (int i = 0; i < 8; ++i) {
    std::string bytes(16 + 8 * i, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    put("fuzz_map_database_values", "edits-" + std::to_string(i), bytes);
  }
}

void bag_seeds(const Scans& scans) {
  {  // a tiny synthetic bag: two scans of eight beams, odometry
    io::rosbag_messages::BagMessages m;
    for (int k = 0; k < 2; ++k) {
      m.scans.push_back({1.0 + k, -1.5, 0.4, 0.1, 30.0, {1.0f, 2.0f, 0.05f, 31.0f, 2.5f, 3.0f, 4.0f, 5.0f}, "laser"});
      m.odometry.push_back({0.9 + k, 0.5 * k, 0.0, 0.0, 0.0, 0.0, 1.0});
    }
    const fs::path tmp = out_root / "tmp.bag";
    io::rosbag_messages::write_bag_messages(tmp.string(), m, false);
    put("fuzz_ros_bag", "tiny.bag", slurp(tmp));
    fs::remove(tmp);
  }
  if (!scans.empty()) {
    io::rosbag_messages::BagMessages m;
    for (const Scan& s : scans) {
      io::rosbag_messages::LaserScanMessage l;
      l.stamp = s.timestamp;
      l.angle_min = -std::numbers::pi / 2;
      const int n = std::max(s.num_beams, 2);
      l.angle_increment = std::numbers::pi / n;
      l.range_min = 0.0;
      l.range_max = 30.0;
      l.ranges.assign(static_cast<std::size_t>(n), std::numeric_limits<float>::infinity());
      for (const Vec2& p : s.points_laser) {
        const long beam = std::lround((std::atan2(p.y(), p.x()) - l.angle_min) / l.angle_increment);
        if (beam >= 0 && beam < n) l.ranges[static_cast<std::size_t>(beam)] = static_cast<float>(p.norm());
      }
      m.scans.push_back(l);
      const Pose2& T = s.T_world_odom;
      m.odometry.push_back({s.timestamp - 0.01, T.x, T.y, 0.0, 0.0, std::sin(T.theta / 2), std::cos(T.theta / 2)});
    }
    const fs::path tmp = out_root / "tmp.bag";
    for (const bool tf : {false, true}) {
      io::rosbag_messages::write_bag_messages(tmp.string(), m, tf);
      put("fuzz_ros_bag", tf ? "first-scans-tf.bag" : "first-scans-odom.bag", slurp(tmp));
    }
    fs::remove(tmp);
  }
  if (have("bags/aces.clf2bag.bag")) put("fuzz_ros_bag", "aces-prefix.bag", slurp(shared / "bags/aces.clf2bag.bag", 24000));
}

// ROS 2 (fuzz_ros2, byte 0: 0 MCAP, 1 .db3): the start of the shared MCAP (its first lz4 chunk, cut), and a small
// .db3 of its first messages, whole and cut.
void ros2_seeds() {
  if (!have("bags/fr079.mcap")) return;
  put("fuzz_ros2", "fr079-prefix.mcap", std::string(1, '\0') + slurp(shared / "bags/fr079.mcap", 40000));
  struct Raw {
    std::string topic, type;
    std::uint64_t time;
    std::string data;
  };
  std::vector<Raw> raw;
  io::mcap::read_messages(
      shared / "bags/fr079.mcap",
      [&](const io::mcap::Channel& c, std::uint64_t t, std::span<const std::uint8_t> d) {
        if (raw.size() < 12) raw.push_back({c.topic, c.schema_name, t, std::string(d.begin(), d.end())});
      },
      false);
  const fs::path tmp = out_root / "tmp.db3";
  fs::remove(tmp);
  {
    const io::sqlite::Connection db = io::sqlite::Connection::open(tmp, io::sqlite::Connection::Access::kCreate);
    db.exec(
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format "
        "TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL); CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id "
        "INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);");
    std::vector<std::string> topics;
    for (const Raw& m : raw) {
      auto at = std::find(topics.begin(), topics.end(), m.topic);
      if (at == topics.end()) {
        topics.push_back(m.topic);
        io::sqlite::Statement(db, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')")
            .bind_int(1, static_cast<std::int64_t>(topics.size()))
            .bind_text(2, m.topic)
            .bind_text(3, m.type)
            .run();
        at = topics.end() - 1;
      }
      io::sqlite::Statement(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)")
          .bind_int(1, at - topics.begin() + 1)
          .bind_int(2, static_cast<std::int64_t>(m.time))
          .bind_blob(3, std::span(reinterpret_cast<const std::uint8_t*>(m.data.data()), m.data.size()))
          .run();
    }
  }
  const std::string db3 = slurp(tmp);
  put("fuzz_ros2", "fr079-first.db3", std::string(1, '\1') + db3);
  put("fuzz_ros2", "fr079-first-cut.db3", std::string(1, '\1') + db3.substr(0, db3.size() * 2 / 3));
  fs::remove(tmp);
}

void map_server_seeds(const Scans& scans) {
  GridMap map;
  if (!scans.empty()) {
    GridMapConfig config;
    config.resolution = 0.25;
    map = build_grid_map(scans, config);
  } else {
    map.resolution = 0.1;
    map.width = 6;
    map.height = 5;
    map.cells.assign(30, CellState::kFree);
    map.cells[7] = map.cells[8] = CellState::kOccupied;
    map.cells[29] = CellState::kUnknown;
  }
  const fs::path dir = out_root / "tmp-map";
  fs::create_directories(dir);
  io::write_map_yaml(dir / "map.yaml", map);
  const std::string yaml = slurp(dir / "map.yaml"), pgm = slurp(dir / "map.pgm");
  fs::remove_all(dir);
  put("fuzz_map_server_yaml", "map.yaml", yaml);
  put("fuzz_map_server_yaml", "map16.yaml", "image: map16.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\n");
  put("fuzz_map_server_yaml", "map2-raw.yaml",
      "image: map2.pgm\nresolution: 1.0\norigin: [-1.0, -2.5, 1.5707]\nnegate: 1\nmode: raw\n"
      "occupied_thresh: 0.9\nfree_thresh: 0.1\n");
  put("fuzz_map_server_yaml", "flow.yaml",
      "{image: \"map.pgm\", resolution: 0.1, origin: [1e3, -1e3, 0], mode: scale, negate: 0} # flow style\n");
  for (int selector = 0; selector < 6; ++selector) put("fuzz_map_server_pgm", "map-" + std::to_string(selector) + ".pgm",
                                                         std::string(1, static_cast<char>(selector)) + pgm);
  // The same image as P2 text, and as a 16-bit P5.
  const std::size_t header_end = pgm.size() - static_cast<std::size_t>(map.width) * map.height;
  std::string p2 = "P2\n" + std::to_string(map.width) + " " + std::to_string(map.height) + "\n255\n";
  std::string p16 = "P5\n" + std::to_string(map.width) + " " + std::to_string(map.height) + "\n65535\n";
  for (std::size_t k = header_end; k < pgm.size(); ++k) {
    const auto v = static_cast<unsigned char>(pgm[k]);
    p2 += std::to_string(v) + ((k - header_end + 1) % static_cast<std::size_t>(map.width) == 0 ? "\n" : " ");
    p16 += static_cast<char>(v), p16 += static_cast<char>(v);
  }
  put("fuzz_map_server_pgm", "map-p2.pgm", std::string(1, '\x02') + p2);
  put("fuzz_map_server_pgm", "map-16.pgm", std::string(1, '\x03') + p16);
}

void point_seeds(const Scans& scans) {
  Points2 points = scans.empty() ? Points2{{0.5, -1.25}, {2.0, 3.0}, {-4.5, 0.125}} : some_points(scans, 60);
  const fs::path dir = out_root / "tmp-points";
  fs::create_directories(dir);
  io::write_points(dir / "p.ply", points, io::PointFormat::kPly);
  io::write_points(dir / "p.csv", points, io::PointFormat::kCsv);
  put("fuzz_points", "points.ply", std::string(1, '\0') + slurp(dir / "p.ply"));
  put("fuzz_points", "points.csv", std::string(1, '\x01') + slurp(dir / "p.csv"));
  fs::remove_all(dir);
}

// Each command's every setting at its default, as --print-config writes it (byte 0: 0 slam, 1 loops, 2 locate).
void config_seeds() {
  put("fuzz_config", "slam.yaml", std::string(1, '\0') + io::config_yaml(SlamConfig{}));
  put("fuzz_config", "loops.yaml", std::string(1, '\x01') + io::config_yaml(io::LoopsConfig{}));
  put("fuzz_config", "locate.yaml", std::string(1, '\x02') + io::config_yaml(io::LocateConfig{}));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: make_fuzz_seeds SHARED_DATA_DIR OUT_DIR\n";
    return 2;
  }
  shared = argv[1];
  out_root = argv[2];
  fs::create_directories(out_root);
  try {
    Scans scans;
    if (have("fr079/fr079-corrected.log.gz")) scans = first_scans("fr079/fr079-corrected.log.gz", 16);
    text_seeds();
    database_seeds(scans);
    bag_seeds(scans);
    ros2_seeds();
    map_server_seeds(scans);
    point_seeds(scans);
    config_seeds();
  } catch (const std::exception& e) {
    std::cerr << "make_fuzz_seeds: " << e.what() << "\n";
    return 1;
  }
  std::cout << "make_fuzz_seeds: " << written << " seeds in " << out_root.string()
            << (fs::is_directory(shared) ? "" : " (no shared data: synthetic seeds only)") << "\n";
  return 0;
}
