// Shared by the libFuzzer targets of fuzz/ (one per reader; fuzz/README.md). The readers take file paths, so each
// input is written to a file in a per-process scratch folder (on tmpfs when /dev/shm exists) and read back.
// InputError is the expected outcome for bad input; anything else that escapes (another exception), a sanitizer
// report, a crash, a timeout or running out of memory is a finding. check() aborts on a broken invariant of what a
// reader returned (e.g. a non-finite point), which is a finding too.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/maps/scan.h"
#include "core/types.h"

namespace partslam::fuzz {

/// The scratch folder of this process, created on first use and removed at exit.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::error_code ec;
    const std::filesystem::path base =
        std::filesystem::is_directory("/dev/shm", ec) ? std::filesystem::path("/dev/shm")
                                                      : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("partslam-fuzz-" + std::to_string(::getpid()));
    std::filesystem::remove_all(d, ec);
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code e;
      std::filesystem::remove_all(scratch_dir(), e);
    });
    return d;
  }();
  return dir;
}

/// Writes bytes to scratch_dir() / name (replacing it) and returns the path.
inline std::filesystem::path write_file(std::string_view name, const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path path = scratch_dir() / name;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    std::perror(path.c_str());
    std::abort();
  }
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

inline std::filesystem::path write_file(std::string_view name, std::string_view text) {
  return write_file(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

/// Aborts (a finding) with a message when a reader's output breaks an invariant.
inline void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
    std::abort();
  }
}

inline bool finite(const Vec2& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }
inline bool finite(const Pose2& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta); }
/// A pose as the readers promise it: finite, within kMaxCoordinate, theta wrapped to [-pi, pi].
inline bool plausible(const Pose2& p) {
  return finite(p) && std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
         std::abs(p.theta) <= 3.1415927;
}

/// What a bag reader (ROS 1 or 2) promises of its scans: some, finite stamps, plausible poses, at most a point per
/// beam, finite points.
inline void check_bag_scans(const Scans& scans) {
  check(!scans.empty(), "scans not empty");
  for (const Scan& s : scans) {
    check(std::isfinite(s.timestamp), "scan timestamp finite");
    check(plausible(s.T_world_laser) && plausible(s.T_world_odom), "scan poses plausible");
    check(s.points_laser.size() <= static_cast<std::size_t>(s.num_beams), "beam count");
    for (const Vec2& p : s.points_laser) check(finite(p), "scan point finite");
  }
}

/// Runs f; an InputError is the expected answer to bad input and ends the run quietly. Returns whether f completed.
template <typename F>
bool expect_input_error(F&& f) {
  try {
    f();
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace partslam::fuzz
