// The structure of a ROS bag 2.0 file, read without librosbag: the checks that come before librosbag reads a
// bag (it trusts every length, offset and time it reads), and the record-by-record walk that reads what is left
// of a bag whose index is missing or damaged. No ROS headers (io/logs/ros_bag_check.cc).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/logs/bag_messages.h"

namespace partslam::io::rosbag_messages {

/// Largest chunk of a bag read, compressed or not [bytes] (rosbag record writes 768 KB chunks).
inline constexpr std::uint32_t kMaxChunkBytes = 256u << 20;

/// Checks the structure of a ROS bag 2.0 file the way librosbag reads it (bag header, index section, chunks, index
/// entries: every length and offset within the file or its chunk, chunks of at most kMaxChunkBytes, bz2 and lz4
/// chunks decompressing to their size); throws BagError naming the first problem. read_bag_messages calls it
/// first: librosbag trusts all of these. (io/logs/ros_bag_check.cc; no ROS headers)
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
/// at a time (at most kMaxChunkBytes). (io/logs/ros_bag_check.cc; no ROS headers)
ChunkWalk walk_bag_chunks(const std::string& path, const std::vector<std::string>& keep_types, bool skip_damaged,
                          std::size_t max_bytes);

}  // namespace partslam::io::rosbag_messages
