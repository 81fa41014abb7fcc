#include "io/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <random>
#include <system_error>

#include "core/error.h"

namespace partslam::io {

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  std::random_device rd;
  return path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(rd() % 1000000));
}

void commit_temporary(const std::filesystem::path& tmp, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path.string() + ": cannot write: " + ec.message());
  }
}

void check_writable(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path.string() + ": is a directory, not an output file");
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(path.string() + ": the folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0) throw InputError(path.string() + ": the folder is not writable");
}

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  check_writable(path);
  const std::filesystem::path tmp = temporary_sibling(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path.string() + ": cannot open for writing");
    write(out);
    out.flush();
    if (!out) throw InputError(path.string() + ": write failed");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  commit_temporary(tmp, path);
}

}  // namespace partslam::io
