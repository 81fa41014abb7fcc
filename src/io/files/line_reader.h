// Line-by-line reading of text files, plain or gzip-compressed (detected by the magic bytes 1f 8b, not
// by the file name). Reads in large blocks and hands out string_views, so parsing a log costs one copy
// of the decompressed text. Every failure — missing file, truncated or corrupt gzip, binary bytes,
// absurdly long lines — is an InputError naming the file and line, so readers built on it never see
// garbage. Used by the CARMEN log and relations readers. A reader that copes with damage itself (the CARMEN
// reader: recordings cut short, LogReadOptions::skip_damaged) asks for Tolerance::kCutAndBinary: a gzip stream
// cut short then ends the input (cut_short()), and lines with control bytes are handed out, flagged by
// binary_column(), instead of throwing.
#pragma once

#include <cstddef>
#include <cstdint>
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

  enum class Tolerance {
    kNone,          ///< every problem throws
    kCutAndBinary,  ///< a truncated gzip stream is the end of the input; binary lines are returned, flagged
  };

  /// Opens path; throws InputError when it is missing, a directory, or unreadable.
  explicit LineReader(const std::filesystem::path& path, Tolerance tolerance = Tolerance::kNone);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// Sets line to the next line without its '\n' (and '\r'); false at the end of the file. The view
  /// stays valid until the next call. Throws InputError on truncated/corrupt gzip data and on lines
  /// holding control bytes (other than tab) or longer than kMaxLineBytes.
  bool next(std::string_view& line);

  /// 1-based number of the line last returned by next() (0 before the first).
  std::size_t line_number() const { return line_number_; }
  /// Byte offset, in the (decompressed) text, of the start of the line last returned by next().
  std::uint64_t line_offset() const { return line_offset_; }
  /// Bytes of (decompressed) text read from the file so far: its whole length once next() has returned false.
  std::uint64_t text_bytes() const { return buffer_offset_ + end_; }
  /// Whether the line last returned ended at the end of the input without a '\n'.
  bool unterminated() const { return unterminated_; }
  /// Kept with Tolerance::kCutAndBinary only: 1-based column of the first control byte of the line last returned,
  /// 0 when it holds none; and that byte.
  std::size_t binary_column() const { return binary_column_; }
  unsigned char binary_byte() const { return binary_byte_; }
  /// With Tolerance::kCutAndBinary: whether the gzip data ended before the end of its stream (the file was cut
  /// short); set once next() has reached the end of the input.
  bool cut_short() const { return cut_short_; }
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
  Tolerance tolerance_ = Tolerance::kNone;
  bool gzipped_ = false;
  std::unique_ptr<Source> source_;
  std::vector<char> buffer_;
  std::size_t begin_ = 0;  ///< start of unconsumed bytes in buffer_
  std::size_t end_ = 0;    ///< end of valid bytes in buffer_
  bool eof_ = false;
  std::size_t line_number_ = 0;
  std::uint64_t buffer_offset_ = 0;  ///< offset in the text of buffer_[0]
  std::uint64_t line_offset_ = 0;
  bool unterminated_ = false;
  std::size_t binary_column_ = 0;
  unsigned char binary_byte_ = 0;
  bool cut_short_ = false;
};

}  // namespace partslam::io
