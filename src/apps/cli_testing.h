// Test helper for the CLI tests: runs the built partslam binary (PARTSLAM_BINARY) and captures its output.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace partslam::testing {

struct CliRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

inline CliRun run_partslam(const std::string& args) {
  const std::string command = std::string("'") + PARTSLAM_BINARY + "' " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (fgets(buffer.data(), buffer.size(), pipe) != nullptr) run.output += buffer.data();
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

inline std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

/// dMM options for the tests whose subject is not the search (a file format, a stretch of a log, threads):
/// the search `loops` makes (4 rotation families, +-3 degrees), about a third of the ranking's default
/// cost, which the sanitizer build pays many times over (make sanitize).
inline const std::string kNarrowDmm = " --dmm-turns 4 --dmm-angular-window 3";

}  // namespace partslam::testing
