#include "io/formats/result_mcap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>

#include "core/error.h"
#include "io/files/atomic_file.h"

namespace partslam::io {
namespace {

// ---- CDR (little endian, XCDR1 as ROS 2 writes it): alignment counts from after the 4-byte encapsulation
// ----

class Cdr {
 public:
  Cdr() : bytes_{0x00, 0x01, 0x00, 0x00} {}
  Cdr& u8(std::uint8_t v) { return put(v); }
  Cdr& i8(std::int8_t v) { return put(v); }
  Cdr& boolean(bool v) { return put(static_cast<std::uint8_t>(v)); }
  Cdr& i32(std::int32_t v) { return put(v); }
  Cdr& u32(std::uint32_t v) { return put(v); }
  Cdr& f32(float v) { return put(v); }
  Cdr& f64(double v) { return put(v); }
  Cdr& string(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  Cdr& count(std::size_t n) { return u32(static_cast<std::uint32_t>(n)); }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

  // builtin_interfaces/Time, std_msgs/Header, geometry_msgs/Pose (a 2D pose: z 0, a turn about z).
  // A time ROS 2 can hold: [0, 2^31) s (a log's absurd or missing stamps are clamped, not cast out of range).
  static double ros_time(double seconds) {
    return std::isfinite(seconds) ? std::clamp(seconds, 0.0, 2147483647.0) : 0.0;
  }
  Cdr& time(double stamp) {
    const double seconds = ros_time(stamp), sec = std::floor(seconds);
    return i32(static_cast<std::int32_t>(sec))
        .u32(static_cast<std::uint32_t>(std::lround((seconds - sec) * 1e9) % 1000000000));
  }
  Cdr& header(double stamp, const std::string& frame) { return time(stamp).string(frame); }
  Cdr& quaternion(double theta) { return f64(0).f64(0).f64(std::sin(theta / 2)).f64(std::cos(theta / 2)); }
  Cdr& pose(const Pose2& p) { return f64(p.x).f64(p.y).f64(0).quaternion(p.theta); }

 private:
  template <class T>
  Cdr& put(T v) {
    while ((bytes_.size() - 4) % sizeof(T) != 0) bytes_.push_back(0);
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));  // little endian: x86 and ARM as ROS 2 runs on them
    bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
    return *this;
  }
  std::vector<std::uint8_t> bytes_;
};

// ---- the message definitions (ros2msg: the type's own, then each dependency under a separator) ----

constexpr const char* kSeparator =
    "================================================================================\n";

std::string definition(const std::string& own, std::initializer_list<const char*> dependencies) {
  std::string out = own;
  for (const char* d : dependencies) out += std::string(kSeparator) + "MSG: " + d;
  return out;
}

constexpr const char* kTime = "builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";
constexpr const char* kDuration = "builtin_interfaces/Duration\nint32 sec\nuint32 nanosec\n";
constexpr const char* kHeader = "std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
constexpr const char* kPoint = "geometry_msgs/Point\nfloat64 x\nfloat64 y\nfloat64 z\n";
constexpr const char* kQuaternion =
    "geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";
constexpr const char* kPose = "geometry_msgs/Pose\nPoint position\nQuaternion orientation\n";
constexpr const char* kVector3 = "geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n";

std::string occupancy_grid_definition() {
  return definition("std_msgs/Header header\nMapMetaData info\nint8[] data\n",
                    {kHeader, kTime,
                     "nav_msgs/MapMetaData\nbuiltin_interfaces/Time map_load_time\nfloat32 resolution\n"
                     "uint32 width\nuint32 height\ngeometry_msgs/Pose origin\n",
                     kPose, kPoint, kQuaternion});
}

std::string path_definition() {
  return definition("std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
                    {kHeader, kTime, "geometry_msgs/PoseStamped\nstd_msgs/Header header\nPose pose\n", kPose,
                     kPoint, kQuaternion});
}

std::string tf_definition() {
  return definition("geometry_msgs/TransformStamped[] transforms\n",
                    {"geometry_msgs/TransformStamped\nstd_msgs/Header header\nstring child_frame_id\n"
                     "Transform transform\n",
                     kHeader, kTime, "geometry_msgs/Transform\nVector3 translation\nQuaternion rotation\n",
                     kVector3, kQuaternion});
}

std::string point_cloud_definition() {
  return definition(
      "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\nbool is_bigendian\n"
      "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
      {kHeader, kTime,
       "sensor_msgs/PointField\nuint8 INT8 = 1\nuint8 UINT8 = 2\nuint8 INT16 = 3\nuint8 UINT16 = 4\n"
       "uint8 INT32 = 5\nuint8 UINT32 = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\nstring name\n"
       "uint32 offset\nuint8 datatype\nuint32 count\n"});
}

// Humble's visualization_msgs/Marker, every field (texture, uv_coordinates and mesh_file included).
std::string marker_array_definition() {
  return definition("visualization_msgs/Marker[] markers\n",
                    {"visualization_msgs/Marker\n"
                     "int32 ARROW = 0\n"
                     "int32 CUBE = 1\n"
                     "int32 SPHERE = 2\n"
                     "int32 CYLINDER = 3\n"
                     "int32 LINE_STRIP = 4\n"
                     "int32 LINE_LIST = 5\n"
                     "int32 CUBE_LIST = 6\n"
                     "int32 SPHERE_LIST = 7\n"
                     "int32 POINTS = 8\n"
                     "int32 TEXT_VIEW_FACING = 9\n"
                     "int32 MESH_RESOURCE = 10\n"
                     "int32 TRIANGLE_LIST = 11\n"
                     "int32 ADD = 0\n"
                     "int32 MODIFY = 0\n"
                     "int32 DELETE = 2\n"
                     "int32 DELETEALL = 3\n"
                     "std_msgs/Header header\n"
                     "string ns\n"
                     "int32 id\n"
                     "int32 type\n"
                     "int32 action\n"
                     "geometry_msgs/Pose pose\n"
                     "geometry_msgs/Vector3 scale\n"
                     "std_msgs/ColorRGBA color\n"
                     "builtin_interfaces/Duration lifetime\n"
                     "bool frame_locked\n"
                     "geometry_msgs/Point[] points\n"
                     "std_msgs/ColorRGBA[] colors\n"
                     "string texture_resource\n"
                     "sensor_msgs/CompressedImage texture\n"
                     "UVCoordinate[] uv_coordinates\n"
                     "string text\n"
                     "string mesh_resource\n"
                     "MeshFile mesh_file\n"
                     "bool mesh_use_embedded_materials\n",
                     kHeader, kTime, kPose, kPoint, kQuaternion, kVector3,
                     "std_msgs/ColorRGBA\nfloat32 r\nfloat32 g\nfloat32 b\nfloat32 a\n", kDuration,
                     "sensor_msgs/CompressedImage\nstd_msgs/Header header\nstring format\nuint8[] data\n",
                     "visualization_msgs/UVCoordinate\nfloat32 u\nfloat32 v\n",
                     "visualization_msgs/MeshFile\nstring filename\nuint8[] data\n"});
}

// ---- the messages ----

std::vector<std::uint8_t> occupancy_grid(const GridMap& m, double stamp) {
  Cdr c;
  c.header(stamp, "map")
      .time(stamp)
      .f32(static_cast<float>(m.resolution))
      .u32(static_cast<std::uint32_t>(m.width));
  c.u32(static_cast<std::uint32_t>(m.height)).pose(m.origin).count(m.cells.size());
  for (const CellState s : m.cells) c.i8(s == CellState::kOccupied ? 100 : s == CellState::kFree ? 0 : -1);
  return c.bytes();
}

std::vector<std::uint8_t> transform(const Scan& s) {
  Cdr c;
  // A Transform (Vector3 translation, Quaternion rotation) is laid out as a Pose (Point, Quaternion).
  c.count(1).header(s.timestamp, "map").string("laser").pose(s.T_world_laser);
  return c.bytes();
}

std::vector<std::uint8_t> point_cloud(const Scan& s) {
  Cdr c;
  c.header(s.timestamp, "laser").u32(1).u32(static_cast<std::uint32_t>(s.points_laser.size())).count(3);
  for (const auto& [name, offset] : {std::pair{"x", 0u}, std::pair{"y", 4u}, std::pair{"z", 8u}})
    c.string(name).u32(offset).u8(7).u32(1);  // FLOAT32
  c.boolean(false)
      .u32(12)
      .u32(static_cast<std::uint32_t>(12 * s.points_laser.size()))
      .count(12 * s.points_laser.size());
  for (const Vec2& p : s.points_laser) {
    for (const float v : {static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f}) {
      std::uint8_t raw[4];
      std::memcpy(raw, &v, 4);
      for (const std::uint8_t b : raw) c.u8(b);
    }
  }
  c.boolean(true);
  return c.bytes();
}

struct Rgba {
  float r, g, b, a;
};

// A MarkerArray of one marker in the map frame: `type` (5 LINE_LIST, 7 SPHERE_LIST), its points, its colour
// (or one per point), `size` its lines' width or its spheres' diameter [m].
std::vector<std::uint8_t> marker(double stamp, const std::string& ns, int type, const Points2& points,
                                 double size, const Rgba& colour, const std::vector<Rgba>& colours = {}) {
  Cdr c;
  c.count(1).header(stamp, "map").string(ns).i32(0).i32(type).i32(0);  // id 0, ADD
  c.pose(Pose2{}).f64(size).f64(size).f64(size);
  c.f32(colour.r).f32(colour.g).f32(colour.b).f32(colour.a);
  c.i32(0).u32(0).boolean(false).count(points.size());  // lifetime forever
  for (const Vec2& p : points) c.f64(p.x()).f64(p.y()).f64(0);
  c.count(colours.size());
  for (const Rgba& k : colours) c.f32(k.r).f32(k.g).f32(k.b).f32(k.a);
  c.string("");                                                // texture_resource
  c.header(stamp, "").string("").count(0).count(0);            // texture (CompressedImage), uv_coordinates
  c.string("").string("").string("").count(0).boolean(false);  // text, mesh_resource, mesh_file, embedded
  return c.bytes();
}

std::vector<std::uint8_t> closure_lines(const std::vector<std::pair<Vec2, Vec2>>& closures, double stamp) {
  Points2 ends;
  for (const auto& [a, b] : closures) ends.push_back(a), ends.push_back(b);
  return marker(stamp, "loop_closures", 5, ends, 0.03, {1.0f, 0.55f, 0.0f, 0.8f});  // orange, as map.png
}

// A nav_msgs/Path of stamped poses in `frame`.
std::vector<std::uint8_t> path(const std::vector<std::pair<double, Pose2>>& poses, const std::string& frame,
                               double stamp) {
  Cdr c;
  c.header(stamp, frame).count(poses.size());
  for (const auto& [t, p] : poses) c.header(t, frame).pose(p);
  return c.bytes();
}

// The scans' laser poses (the log's odometry: T_world_odom, in "odom"; else the corrected ones, in "map").
std::vector<std::uint8_t> path(const Scans& scans, bool odometry, double stamp) {
  std::vector<std::pair<double, Pose2>> poses;
  for (const Scan& s : scans) poses.emplace_back(s.timestamp, odometry ? s.T_world_odom : s.T_world_laser);
  return path(poses, odometry ? "odom" : "map", stamp);
}

// ---- MCAP records ----

class McapOut {
 public:
  explicit McapOut(std::ostream& out) : out_(out) {
    const unsigned char magic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
    out_.write(reinterpret_cast<const char*>(magic), 8);
    record(0x01, Bytes().string("ros2").string("partslam"));  // Header: profile, library
  }
  std::uint16_t channel(const std::string& topic, const std::string& type, const std::string& schema) {
    const auto id = static_cast<std::uint16_t>(++channels_);
    record(0x03, Bytes().u16(id).string(type).string("ros2msg").bytes(schema));  // Schema
    record(0x04, Bytes().u16(id).u16(id).string(topic).string("cdr").u32(0));    // Channel
    return id;
  }
  void message(std::uint16_t channel, double stamp, const std::vector<std::uint8_t>& data) {
    const auto ns = static_cast<std::uint64_t>(std::llround(Cdr::ros_time(stamp) * 1e9));
    Bytes b;
    b.u16(channel).u32(sequence_++).u64(ns).u64(ns);
    b.out.insert(b.out.end(), data.begin(), data.end());
    record(0x05, b);
  }
  void finish() {
    record(0x0F, Bytes().u32(0));                // DataEnd (no CRC)
    record(0x02, Bytes().u64(0).u64(0).u32(0));  // Footer: no summary
    const unsigned char magic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
    out_.write(reinterpret_cast<const char*>(magic), 8);
  }

 private:
  struct Bytes {
    std::vector<std::uint8_t> out;
    template <class T>
    Bytes& le(T v) {
      for (std::size_t k = 0; k < sizeof(T); ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
      return *this;
    }
    Bytes& u16(std::uint16_t v) { return le(v); }
    Bytes& u32(std::uint32_t v) { return le(v); }
    Bytes& u64(std::uint64_t v) { return le(v); }
    Bytes& string(const std::string& s) {
      u32(static_cast<std::uint32_t>(s.size()));
      out.insert(out.end(), s.begin(), s.end());
      return *this;
    }
    Bytes& bytes(const std::string& s) { return string(s); }
  };
  void record(std::uint8_t op, const Bytes& b) {
    Bytes head;
    head.out.push_back(op);
    head.u64(b.out.size());
    out_.write(reinterpret_cast<const char*>(head.out.data()), static_cast<std::streamsize>(head.out.size()));
    out_.write(reinterpret_cast<const char*>(b.out.data()), static_cast<std::streamsize>(b.out.size()));
  }
  std::ostream& out_;
  int channels_ = 0;
  std::uint32_t sequence_ = 0;
};

}  // namespace

void write_located_mcap(const std::filesystem::path& file, const GridMap& map,
                        const std::vector<LocatedPose>& located) {
  if (located.empty()) throw InputError(file.string() + ": no answer to write");
  const double end = located.back().stamp;
  std::vector<std::pair<double, Pose2>> poses;
  Points2 points;
  std::vector<Rgba> colours;
  for (const LocatedPose& l : located) {
    poses.emplace_back(l.stamp, l.robot);
    points.push_back(l.robot.translation());
    colours.push_back(l.confident ? Rgba{0.1f, 0.7f, 0.2f, 1.0f}
                                  : Rgba{1.0f, 0.55f, 0.0f, 1.0f});  // as the plot
  }
  write_atomically(file, [&](std::ostream& out) {
    McapOut mcap(out);
    const auto map_channel = mcap.channel("/map", "nav_msgs/msg/OccupancyGrid", occupancy_grid_definition());
    const auto path_channel = mcap.channel("/located/path", "nav_msgs/msg/Path", path_definition());
    const auto answers =
        mcap.channel("/located", "visualization_msgs/msg/MarkerArray", marker_array_definition());
    mcap.message(map_channel, end, occupancy_grid(map, end));
    mcap.message(path_channel, end, path(poses, "map", end));
    mcap.message(answers, end, marker(end, "located", 7, points, 0.3, {1, 1, 1, 1}, colours));
    mcap.finish();
  });
}

void write_result_mcap(const std::filesystem::path& file, const SlamResultLayers& layers) {
  if (layers.map == nullptr || layers.corrected == nullptr || layers.corrected->empty())
    throw InputError(file.string() + ": a result needs the map and the corrected scans");
  const Scans& scans = *layers.corrected;
  const double end = scans.back().timestamp;
  write_atomically(file, [&](std::ostream& out) {
    McapOut mcap(out);
    const auto map = mcap.channel("/map", "nav_msgs/msg/OccupancyGrid", occupancy_grid_definition());
    const auto slam_path = mcap.channel("/slam/path", "nav_msgs/msg/Path", path_definition());
    const auto odom_path = mcap.channel("/odom/path", "nav_msgs/msg/Path", path_definition());
    const auto closures =
        mcap.channel("/loop_closures", "visualization_msgs/msg/MarkerArray", marker_array_definition());
    const auto tf = mcap.channel("/tf", "tf2_msgs/msg/TFMessage", tf_definition());
    const auto cloud = mcap.channel("/scan", "sensor_msgs/msg/PointCloud2", point_cloud_definition());
    for (const Scan& s : scans) {
      mcap.message(tf, s.timestamp, transform(s));
      mcap.message(cloud, s.timestamp, point_cloud(s));
    }
    mcap.message(map, end, occupancy_grid(*layers.map, end));
    mcap.message(slam_path, end, path(scans, false, end));
    if (layers.odometry != nullptr && !layers.odometry->empty())
      mcap.message(odom_path, end, path(*layers.odometry, true, end));
    mcap.message(closures, end, closure_lines(layers.closures, end));
    mcap.finish();
  });
}

}  // namespace partslam::io
