// Atomic file writes: content goes to a temporary file beside the target, which is renamed over the
// target only once it is complete, so a failure never leaves a half-written output behind.
//
// A path that is a symbolic link is written through: the file it names is replaced, the link stays. A path
// that names something other than a regular file (a FIFO, a device such as /dev/stdout) is written in place,
// as a stream: there is nothing to replace atomically. "-" is refused (it would be a file named "-").
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace partslam::io {

/// Calls write(stream) on a temporary file and renames it to path on success. Throws InputError naming
/// the path when the file cannot be written; the temporary file is removed on any failure.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// Checks, before any work, that an output file can be written at path: its folder exists and is writable,
/// and path is not a folder. Throws InputError naming the path and the reason.
void check_writable(const std::filesystem::path& path);

/// A command's file, named by its flag (or argument) for messages.
struct NamedPath {
  std::string flag;
  std::filesystem::path path;  ///< empty: not given
};

/// check_writable for each given output, and, before any work, that no output is one of the command's inputs
/// (writing it would destroy the input) and that no two outputs are the same file. Throws InputError naming
/// both flags and the path.
void check_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs);

/// A temporary path beside the file path writes to, for writers that need a file name (SQLite, cairo); the
/// caller commits it with commit_temporary.
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

/// Renames tmp over the file path writes to (copies it into path, and removes it, where path is a FIFO or a
/// device); on failure removes tmp and throws InputError.
void commit_temporary(const std::filesystem::path& tmp, const std::filesystem::path& path);

}  // namespace partslam::io
