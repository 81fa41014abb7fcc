// Helpers shared by the io tests: scratch files (plain or gzip) in a per-test temporary folder, and
// the location of the shared real-data folder. Test-only; not part of the library.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>

namespace partslam::io::testing {

/// A fresh temporary folder, removed with its content on destruction.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("partslam_") + (info != nullptr ? info->name() : "test") + "_" +
                       std::to_string(::getpid());
    for (char& c : name) {
      if (c == '/') c = '_';
    }
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::filesystem::path operator/(std::string_view file) const { return path_ / file; }

 private:
  std::filesystem::path path_;
};

inline void write_bytes(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Writes text to path, gzip-compressed when gzipped is true.
inline void write_text(const std::filesystem::path& path, std::string_view text, bool gzipped) {
  if (!gzipped) {
    write_bytes(path, text);
    return;
  }
  gzFile gz = gzopen(path.c_str(), "wb");
  gzwrite(gz, text.data(), static_cast<unsigned>(text.size()));
  gzclose(gz);
}

/// The real-data folder: $PARTSLAM_SHARED_DATA if set (worktrees live elsewhere), else the compiled-in path.
inline std::filesystem::path shared_data() {
  const char* env = std::getenv("PARTSLAM_SHARED_DATA");
  return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                        : std::filesystem::path(PARTSLAM_SHARED_DATA);
}

}  // namespace partslam::io::testing
