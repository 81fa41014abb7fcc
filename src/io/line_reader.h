// Line-by-line reading of text files, plain or gzip-compressed (detected by the magic bytes 1f 8b, not
// by the file name). Reads in large blocks and hands out string_views, so parsing a log costs one copy
// of the decompressed text. Every failure — missing file, truncated or corrupt gzip, binary bytes,
// absurdly long lines — is an InputError naming the file and line, so readers built on it never see
// garbage. Used by the CARMEN log and relations readers.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace partslam::io {

class LineReader {
 public:
  /// Longest accepted line [bytes]; a longer one is an InputError (guards against binary input).
  static constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

  /// Opens path; throws InputError when it is missing, a directory, or unreadable.
  explicit LineReader(const std::filesystem::path& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// Sets line to the next line without its '\n' (and '\r'); false at the end of the file. The view
  /// stays valid until the next call. Throws InputError on truncated/corrupt gzip data and on lines
  /// holding control bytes (other than tab) or longer than kMaxLineBytes.
  bool next(std::string_view& line);

  /// 1-based number of the line last returned by next() (0 before the first).
  std::size_t line_number() const { return line_number_; }
  /// The path as given, for messages.
  const std::string& name() const { return name_; }
  bool gzipped() const { return gzipped_; }

  /// Throws InputError "<name>:<line>: <what>".
  [[noreturn]] void fail(std::string_view what) const;

 private:
  struct Source;
  /// Reads more bytes behind end_; returns false at the end of the input.
  bool fill();

  std::string name_;
  bool gzipped_ = false;
  std::unique_ptr<Source> source_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;  ///< start of unconsumed bytes in buffer_
  std::size_t end_ = 0;    ///< end of valid bytes in buffer_
  bool eof_ = false;
  std::size_t line_number_ = 0;
};

}  // namespace partslam::io
