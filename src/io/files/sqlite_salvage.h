// The rows a SQLite file cut short still holds. SQLite itself cannot read such a file (its b-tree's interior pages
// may lie past the cut), so this walks the file's pages in order and decodes every table leaf cell whose record,
// overflow pages included, lies whole before the cut (the file format: https://www.sqlite.org/fileformat2.html).
// Used for rosbag2 .db3 recordings cut short (io/logs/ros2_bag.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <variant>
#include <vector>

namespace partslam::io::sqlite {

/// One column value of a salvaged row: NULL, an integer, a real, or text / blob bytes.
using Value = std::variant<std::monostate, std::int64_t, double, std::span<const std::uint8_t>>;

/// What a SQLite file's 100-byte header says of its pages.
struct FileHeader {
  std::size_t page_size = 0;   ///< bytes 16-17, big endian, 1 for 65536
  std::size_t reserved = 0;    ///< byte 20: bytes at the end of each page not used by cells
  std::uint64_t page_count = 0;  ///< bytes 28-31: the pages the file holds when whole
};

/// The header of the file, or nullopt when it does not start with "SQLite format 3\0" (or is shorter than 100
/// bytes). A file shorter than page_size * page_count was cut short.
std::optional<FileHeader> read_file_header(const std::filesystem::path& path);

/// Calls on_row(rowid, values) for every whole row of every table leaf page of the file, in page order (a row
/// may come from a stale page; callers keep the last of a rowid if they must). Throws InputError naming the file
/// when it does not start with the SQLite header. Never reads outside the file.
void salvage_rows(const std::filesystem::path& path,
                  const std::function<void(std::int64_t rowid, const std::vector<Value>& values)>& on_row);

}  // namespace partslam::io::sqlite
