#include "io/files/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <random>
#include <system_error>

#include "core/error.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;

// Whether path exists as something other than a regular file or a folder (following links): written in place.
bool is_stream(const fs::path& path) {
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);
  return !ec && fs::exists(s) && !fs::is_regular_file(s) && !fs::is_directory(s);
}

// The file a write to path replaces: path with its symbolic links followed (a dangling link: the file it
// names).
fs::path target(const fs::path& path) {
  if (path == "-") throw InputError("-: not an output file name (to print, give /dev/stdout)");
  fs::path p = path;
  std::error_code ec;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    if (hops == 40) throw InputError(path.string() + ": too many levels of symbolic links");
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) throw InputError(path.string() + ": cannot read the link: " + ec.message());
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p;
}

// Whether a and b name the same file; false when either does not exist.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  const bool same = fs::equivalent(a, b, ec);
  return !ec && same;
}

// Whether a and b name the same file that may not exist yet (their folders resolved).
bool same_name(const fs::path& a, const fs::path& b) {
  std::error_code ec_a, ec_b;
  const fs::path ca = fs::weakly_canonical(target(a), ec_a), cb = fs::weakly_canonical(target(b), ec_b);
  return !ec_a && !ec_b && ca == cb;
}

}  // namespace

std::filesystem::path temporary_sibling(const std::filesystem::path& path) {
  std::random_device rd;
  const fs::path to = is_stream(path) ? fs::temp_directory_path() / path.filename() : target(path);
  return to.parent_path() / ("." + to.filename().string() + ".tmp" + std::to_string(rd() % 1000000));
}

void commit_temporary(const std::filesystem::path& tmp, const std::filesystem::path& path) {
  std::error_code ec;
  if (is_stream(path)) {
    std::ifstream in(tmp, std::ios::binary);
    std::ofstream out(path, std::ios::binary);
    const bool ok = in && out && (out << in.rdbuf()) && out.flush();
    fs::remove(tmp, ec);
    if (!ok) throw InputError(path.string() + ": cannot write");
    return;
  }
  fs::rename(tmp, target(path), ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path.string() + ": cannot write: " + ec.message());
  }
}

void check_writable(const std::filesystem::path& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path.string() + ": is a directory, not an output file");
  if (is_stream(path)) {
    if (::access(path.c_str(), W_OK) != 0) throw InputError(path.string() + ": is not writable");
    return;
  }
  const fs::path file = target(path);
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec))
    throw InputError(path.string() + ": the folder " + folder.string() + " does not exist");
  if (::access(folder.c_str(), W_OK) != 0) throw InputError(path.string() + ": the folder is not writable");
}

void check_outputs(const std::vector<NamedPath>& outputs, const std::vector<NamedPath>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& out = outputs[i];
    if (out.path.empty()) continue;
    check_writable(out.path);
    for (const NamedPath& in : inputs)
      if (!in.path.empty() && same_file(out.path, in.path))
        throw InputError(out.path.string() + ": " + out.flag + " is the file " + in.flag +
                         " reads; writing it would destroy it: choose another output file");
    for (std::size_t j = 0; j < i; ++j) {
      const fs::path& other = outputs[j].path;
      if (!other.empty() && !is_stream(out.path) &&
          (same_file(out.path, other) || same_name(out.path, other)))
        throw InputError(out.path.string() + ": given both as " + outputs[j].flag + " and as " + out.flag);
    }
  }
}

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  check_writable(path);
  // A FIFO or a device is written in place, as a stream: there is nothing to replace atomically.
  const bool stream = is_stream(path);
  const fs::path file = stream ? path : temporary_sibling(path);
  try {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path.string() + ": cannot open for writing");
    write(out);
    out.flush();
    if (!out) throw InputError(path.string() + ": write failed");
  } catch (...) {
    std::error_code ec;
    if (!stream) fs::remove(file, ec);
    throw;
  }
  if (!stream) commit_temporary(file, path);
}

}  // namespace partslam::io
