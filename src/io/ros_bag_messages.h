// The raw messages of a ROS 1 bag that io/ros_bag.h turns into scans, read by the one translation unit that
// includes ROS headers (compiled as C++17: ROS 1's generated messages use std::allocator<void>::rebind, which
// C++20 removed). Plain standard-library types only, so this header compiles in both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace partslam::io::rosbag_messages {

/// A frame id as tf2 spells it: without the leading '/' that ROS 1 allowed.
inline std::string bare_frame(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

struct LaserScanMessage {
  double stamp = 0.0;  ///< header.stamp [s]
  double angle_min = 0.0, angle_increment = 0.0, range_min = 0.0, range_max = 0.0;
  std::vector<float> ranges;
  std::string frame_id;  ///< header.frame_id, without a leading '/'
};

struct OdometryMessage {
  double stamp = 0.0;
  double x = 0.0, y = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
};

/// A transform between two frames other than odom -> base (e.g. base_link -> laser on /tf_static): the pose of
/// `child` in `parent`.
struct FrameTransform {
  std::string parent, child;  ///< without a leading '/'
  double x = 0.0, y = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
};

struct BagMessages {
  std::string scan_topic;      ///< the first sensor_msgs/LaserScan topic; only its messages are kept
  std::string odometry_topic;  ///< the first nav_msgs/Odometry topic; without one, the tf2_msgs/TFMessage topic
                               ///< (e.g. /tf) whose odom -> base_link (or base_footprint) transforms pose the
                               ///< scans, named "TOPIC (odom -> CHILD)"; empty when there is neither
  std::string base_frame;      ///< the frame the odometry poses (Odometry child_frame_id, or the /tf child)
  std::vector<LaserScanMessage> scans;
  std::vector<OdometryMessage> odometry;
  std::vector<FrameTransform> transforms;  ///< the first of every other parent -> child pair, on any tf topic
  /// What was read past: a bag cut short or without its index, damaged chunks or messages skipped (skip_damaged).
  /// Without the file's name (the caller adds it).
  std::vector<std::string> warnings;
};

/// Why a bag could not be read (the caller names the file).
struct BagError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Largest chunk of a bag read, compressed or not [bytes] (rosbag record writes 768 KB chunks).
inline constexpr std::uint32_t kMaxChunkBytes = 256u << 20;

/// Checks the structure of a ROS bag 2.0 file the way librosbag reads it (bag header, index section, chunks, index
/// entries: every length and offset within the file or its chunk, chunks of at most kMaxChunkBytes, bz2 and lz4
/// chunks decompressing to their size); throws BagError naming the first problem. read_bag_messages calls it
/// first: librosbag trusts all of these. (io/ros_bag_check.cc; no ROS headers)
void check_bag_structure(const std::string& path);

/// A connection (topic and message type) of a bag.
struct BagConnection {
  std::string topic, datatype, md5sum;
};

/// A message record met by walk_bag_chunks.
struct RawMessage {
  std::size_t connection = 0;  ///< index in ChunkWalk::connections
  std::uint64_t time = 0;      ///< the record's time: seconds << 32 | nanoseconds
  std::uint64_t position = 0;  ///< where its chunk (or the record itself) starts in the file [bytes]
  std::vector<std::uint8_t> data;
};

/// What walk_bag_chunks found.
struct ChunkWalk {
  std::vector<BagConnection> connections;
  std::vector<RawMessage> messages;  ///< the kept messages, in file order
  std::size_t chunks = 0;            ///< whole chunks read
  std::uint64_t file_size = 0;
  std::uint64_t index_pos = 0;       ///< the bag header's index_pos (0: the recording was never closed)
  std::uint64_t cut_at = 0;          ///< start of the record the file ends in the middle of; 0: none
  std::size_t indexed_chunks = 0;    ///< chunks the bag's index lists when it was readable; 0: not read
  std::size_t damaged = 0;           ///< damaged chunks or records skipped (skip_damaged)
  std::string first_damage;          ///< "the record at byte P is damaged: problem" of the first
  std::uint64_t lost_at = 0;         ///< with skip_damaged and no readable index: the damaged record after which
                                     ///< no further chunk record was found (the rest unread); 0: none
};

/// Walks a ROS bag 2.0 file record by record from its bag header on, as `rosbag reindex` does: the connection
/// records and the messages in the chunks (bz2, lz4 or none), keeping only the messages whose type is one of
/// keep_types. When the bag's index (at the header's index_pos) reads whole, its connections are known from the
/// start and its chunk positions bound the walk, which stops at the index. A record running past the end of the
/// file ends the walk (cut_at) only when the file ends before index_pos (or index_pos is 0: never closed); before
/// an index that lies within the file it is damage. A damaged record or chunk throws BagError naming its
/// position (and skip_damaged), or with skip_damaged is skipped and counted: the walk resumes at the next chunk
/// the index gives (a record whose lengths run over that chunk is damaged too), or without a readable index at
/// the record's end when its lengths lie within the file, else at the next record found that reads as a chunk
/// record (at most 64 such searches; when none is found the rest is given up: lost_at). Throws BagError when the
/// kept messages pass max_bytes (their data and 64 bytes each), and for a file that is not a bag. Reads one chunk
/// at a time (at most kMaxChunkBytes). (io/ros_bag_check.cc; no ROS headers)
ChunkWalk walk_bag_chunks(const std::string& path, const std::vector<std::string>& keep_types, bool skip_damaged,
                          std::size_t max_bytes);

/// Reads the messages in bag order, chosen as io/bag_selection.h says (scan_topic / odom_topic: the topics asked
/// for, empty: the first); stops with BagError once more than max_ranges ranges were read. A bag that fails
/// check_bag_structure is read by walk_bag_chunks, in the order of the messages' times: one whose index is
/// missing or cut off (a recording cut short before its index, or never closed) up to its last whole chunk, with
/// a warning. Damage elsewhere (a corrupt chunk or chunk length in a bag whose file goes on to its index, a
/// message whose arrays do not fit it, a damaged index) throws BagError naming the place, or with skip_damaged is
/// skipped and counted in a warning, every other whole chunk read (found from the index when it is readable).
BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges, bool skip_damaged = false,
                              const std::string& scan_topic = "", const std::string& odom_topic = "");

/// Writes the scans on /scan (frame "laser") and the odometry on /odom (nav_msgs/Odometry, frame odom ->
/// base_link) or, with as_tf, as /tf transforms odom -> base_link, and the other transforms once on /tf_static:
/// bags like a robot records them, for tests and conversions.
void write_bag_messages(const std::string& path, const BagMessages& messages, bool as_tf);

}  // namespace partslam::io::rosbag_messages
