// Reading MCAP files (https://mcap.dev/spec), the container ROS 2 records to by default since Iron: the records
// of the data section in file order, chunks opened (uncompressed, lz4 frames or zstd; their CRC checked when
// set), schemas and channels resolved, each message handed on with its channel. The summary section and the
// indexes are not needed and not read, so a file cut short still yields every message before the cut.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>

namespace partslam::io::mcap {

struct Channel {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;  ///< e.g. "cdr"
  std::string schema_name;       ///< e.g. "sensor_msgs/msg/LaserScan"; empty without a schema
  std::string schema_encoding;   ///< e.g. "ros2msg"
};

/// How the data section ended.
struct ReadReport {
  std::uint64_t file_bytes = 0;
  std::uint64_t messages = 0;
  /// The file ends inside a record (or before the data section's end): it was read up to the last whole record,
  /// which ends at byte read_bytes, and the whole messages of a chunk cut short (as far as its compressed bytes
  /// decompress).
  bool truncated = false;
  std::uint64_t read_bytes = 0;
  std::uint64_t cut_chunk_records = 0;  ///< records read from the first part of a chunk the cut went through
  /// Chunks that could not be opened (corrupt compression, CRC mismatch, malformed records inside), skipped
  /// because skip_damaged was set; without it the first one is an error.
  std::size_t damaged_chunks = 0;
  std::string first_damage;  ///< where and what the first skipped damage was
};

using MessageHandler = std::function<void(const Channel& channel, std::uint64_t log_time_ns,
                                          std::span<const std::uint8_t> data)>;

/// Reads every message of the file in file order. Throws InputError naming the file and byte offset for a file
/// that is not MCAP, a record or chunk larger than 256 MB, a message on an unknown channel, or (without
/// skip_damaged) a damaged chunk.
ReadReport read_messages(const std::filesystem::path& path, const MessageHandler& on_message, bool skip_damaged);

/// True when the file starts with the MCAP magic bytes.
bool has_mcap_magic(const std::filesystem::path& path);

}  // namespace partslam::io::mcap
