// Tested by: io/logs/carmen_log_test.cc, io/logs/relations_test.cc

#include "io/files/line_reader.h"

#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

#include "core/error.h"

namespace partslam::io {
namespace {

constexpr std::size_t kBlockBytes = std::size_t{256} << 10;

std::string hex_byte(unsigned char c) {
  static constexpr char kDigits[] = "0123456789abcdef";
  return {'0', 'x', kDigits[c >> 4], kDigits[c & 15]};
}

}  // namespace

struct LineReader::Source {
  std::FILE* file = nullptr;
  gzFile gz = nullptr;
  ~Source() {
    if (file != nullptr) std::fclose(file);
    if (gz != nullptr) gzclose(gz);
  }
};

LineReader::LineReader(const std::filesystem::path& path, Tolerance tolerance)
    : name_(path.string()), tolerance_(tolerance), source_(std::make_unique<Source>()) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(name_ + ": is a directory, not a file");
  source_->file = std::fopen(path.c_str(), "rb");
  if (source_->file == nullptr) {
    throw InputError(name_ + ": cannot open: " + std::generic_category().message(errno));
  }
  unsigned char magic[2] = {0, 0};
  const std::size_t got = std::fread(magic, 1, 2, source_->file);
  gzipped_ = got == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
  if (gzipped_) {
    std::fclose(source_->file);
    source_->file = nullptr;
    source_->gz = gzopen(path.c_str(), "rb");
    if (source_->gz == nullptr) throw InputError(name_ + ": cannot open gzip stream");
    gzbuffer(source_->gz, static_cast<unsigned>(kBlockBytes));
  } else if (std::fseek(source_->file, 0, SEEK_SET) != 0) {
    throw InputError(name_ + ": cannot rewind: " + std::generic_category().message(errno));
  }
  buffer_.resize(kBlockBytes);
}

LineReader::~LineReader() = default;

void LineReader::fail(std::string_view what) const {
  throw InputError(name_ + ":" + std::to_string(line_number_) + ": " + std::string(what));
}

bool LineReader::fill() {
  char* dst = buffer_.data() + end_;
  const std::size_t room = buffer_.size() - end_;
  if (source_->gz != nullptr) {
    const int n = gzread(source_->gz, dst, static_cast<unsigned>(room));
    int errnum = Z_OK;
    const char* message = gzerror(source_->gz, &errnum);
    if (n <= 0 && errnum == Z_BUF_ERROR && tolerance_ == Tolerance::kCutAndBinary) {
      cut_short_ = true;  // the stream ends early: what was decompressed is the input
      return false;
    }
    if (n < 0 || (n == 0 && errnum != Z_OK)) {
      ++line_number_;  // the line being read when the data ran out
      if (errnum == Z_BUF_ERROR) fail("truncated gzip data (unexpected end of file)");
      fail(std::string("corrupt gzip data: ") + (message != nullptr ? message : "unknown zlib error"));
    }
    end_ += static_cast<std::size_t>(n);
    return n > 0;
  }
  const std::size_t n = std::fread(dst, 1, room, source_->file);
  if (n == 0 && std::ferror(source_->file) != 0) {
    ++line_number_;
    fail("read error: " + std::generic_category().message(errno));
  }
  end_ += n;
  return n > 0;
}

bool LineReader::next(std::string_view& line) {
  std::size_t scanned = 0;  // bytes after begin_ already known to hold no '\n'
  const char* newline = nullptr;
  while (true) {
    const std::size_t from = begin_ + scanned;
    newline = static_cast<const char*>(std::memchr(buffer_.data() + from, '\n', end_ - from));
    if (newline != nullptr || eof_) break;
    scanned = end_ - begin_;
    if (scanned > kMaxLineBytes) {
      ++line_number_;
      fail("line longer than " + std::to_string(kMaxLineBytes) + " bytes (binary data?)");
    }
    if (begin_ > 0) {  // move the partial line to the front to make room
      std::memmove(buffer_.data(), buffer_.data() + begin_, scanned);
      buffer_offset_ += begin_;
      begin_ = 0;
      end_ = scanned;
    }
    if (end_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);
    if (!fill()) eof_ = true;
  }
  const char* start = buffer_.data() + begin_;
  line_offset_ = buffer_offset_ + begin_;
  unterminated_ = newline == nullptr;
  std::size_t length = 0;
  if (newline != nullptr) {
    length = static_cast<std::size_t>(newline - start);
    begin_ += length + 1;
  } else {
    if (begin_ == end_) return false;
    length = end_ - begin_;
    begin_ = end_;
  }
  ++line_number_;
  if (length > kMaxLineBytes) fail("line longer than " + std::to_string(kMaxLineBytes) + " bytes");
  if (length > 0 && start[length - 1] == '\r') --length;
  binary_column_ = 0;
  for (std::size_t i = 0; i < length; ++i) {
    const auto c = static_cast<unsigned char>(start[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) {
      if (tolerance_ == Tolerance::kNone)
        fail("binary data (byte " + hex_byte(c) + " at column " + std::to_string(i + 1) + ")");
      binary_column_ = i + 1;
      binary_byte_ = c;
      break;
    }
  }
  line = std::string_view(start, length);
  return true;
}

}  // namespace partslam::io
