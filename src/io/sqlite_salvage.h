// The rows a SQLite file cut short still holds. SQLite itself cannot read such a file (its b-tree's interior pages
// may lie past the cut), so this walks the file's pages in order and decodes every table leaf cell whose record,
// overflow pages included, lies whole before the cut (the file format: https://www.sqlite.org/fileformat2.html).
// Used for rosbag2 .db3 recordings cut short (io/ros2_bag.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <variant>
#include <vector>

namespace partslam::io::sqlite {

/// One column value of a salvaged row: NULL, an integer, a real, or text / blob bytes.
using Value = std::variant<std::monostate, std::int64_t, double, std::span<const std::uint8_t>>;

/// Calls on_row(rowid, values) for every whole row of every table leaf page of the file, in page order (a row
/// may come from a stale page; callers keep the last of a rowid if they must). Throws InputError naming the file
/// when it does not start with the SQLite header. Never reads outside the file.
void salvage_rows(const std::filesystem::path& path,
                  const std::function<void(std::int64_t rowid, const std::vector<Value>& values)>& on_row);

}  // namespace partslam::io::sqlite
