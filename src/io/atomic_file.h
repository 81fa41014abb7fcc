// Atomic file writes: content goes to a temporary file beside the target, which is renamed over the
// target only once it is complete, so a failure never leaves a half-written output behind.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace partslam::io {

/// Calls write(stream) on a temporary file and renames it to path on success. Throws InputError naming
/// the path when the file cannot be written; the temporary file is removed on any failure.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// Checks, before any work, that an output file can be written at path: its folder exists and is writable,
/// and path is not a folder. Throws InputError naming the path and the reason.
void check_writable(const std::filesystem::path& path);

/// A temporary path beside path, for writers that need a file name (SQLite, cairo); caller renames it.
std::filesystem::path temporary_sibling(const std::filesystem::path& path);

/// Renames tmp over path; on failure removes tmp and throws InputError.
void commit_temporary(const std::filesystem::path& tmp, const std::filesystem::path& path);

}  // namespace partslam::io
