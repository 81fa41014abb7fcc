#include "io/logs/mcap_file.h"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "core/error.h"

namespace partslam::io::mcap {
namespace {

constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr std::uint64_t kMaxRecordBytes = 256ull << 20;  // a chunk or message; rosbag2 writes 768 KB chunks

enum Opcode : std::uint8_t {
  kHeader = 0x01, kFooter = 0x02, kSchema = 0x03, kChannel = 0x04, kMessage = 0x05, kChunk = 0x06,
  kChunkIndex = 0x08, kDataEnd = 0x0F,
};

std::uint64_t le64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

// A malformed record inside a chunk or record: caught and reported with the record's offset.
struct Malformed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Little-endian fields of one record's bytes.
struct Fields {
  std::span<const std::uint8_t> b;
  std::size_t at = 0;
  const std::uint8_t* take(std::uint64_t n) {
    if (n > b.size() - at) throw Malformed("a field runs past its record");
    const std::uint8_t* p = b.data() + at;
    at += static_cast<std::size_t>(n);
    return p;
  }
  template <typename T>
  T number() {
    T v = 0;
    const std::uint8_t* p = take(sizeof(T));
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<T>(static_cast<T>(p[i]) << (8 * i));
    return v;
  }
  std::string string() {
    const std::uint32_t n = number<std::uint32_t>();
    return std::string(reinterpret_cast<const char*>(take(n)), n);
  }
  std::span<const std::uint8_t> rest() { return b.subspan(at); }
};

struct Schema {
  std::string name, encoding;
};

class Reader {
 public:
  Reader(const std::filesystem::path& path, const MessageHandler& on_message, bool skip_damaged)
      : name_(path.string()), on_message_(on_message), skip_damaged_(skip_damaged) {}

  // One record (top level or inside a chunk) at the given file offset (for messages).
  void record(std::uint8_t op, std::span<const std::uint8_t> bytes, std::uint64_t offset) {
    Fields f{bytes};
    if (op == kSchema) {
      const std::uint16_t id = f.number<std::uint16_t>();
      Schema s;
      s.name = f.string();
      s.encoding = f.string();
      schemas_[id] = std::move(s);
    } else if (op == kChannel) {
      Channel c;
      c.id = f.number<std::uint16_t>();
      const std::uint16_t schema = f.number<std::uint16_t>();
      c.topic = f.string();
      c.message_encoding = f.string();
      if (schema != 0) {
        const auto s = schemas_.find(schema);
        if (s == schemas_.end()) throw Malformed("channel " + c.topic + " names schema " + std::to_string(schema) +
                                                 ", which no earlier record defines");
        c.schema_name = s->second.name, c.schema_encoding = s->second.encoding;
      }
      channels_[c.id] = std::move(c);
    } else if (op == kMessage) {
      const std::uint16_t channel = f.number<std::uint16_t>();
      f.number<std::uint32_t>();  // sequence
      const std::uint64_t log_time = f.number<std::uint64_t>();
      f.number<std::uint64_t>();  // publish time
      const auto c = channels_.find(channel);
      if (c == channels_.end())
        throw InputError(name_ + ": byte " + std::to_string(offset) + ": a message on channel " +
                         std::to_string(channel) + ", which no earlier record defines");
      ++report_.messages;
      on_message_(c->second, log_time, f.rest());
    }
  }

  // Hands on the chunk's messages; false when it is damaged (and skipped with skip_damaged).
  bool chunk(std::span<const std::uint8_t> bytes, std::uint64_t offset) {
    std::vector<std::uint8_t> records;
    try {
      Fields f{bytes};
      f.number<std::uint64_t>();  // message start time
      f.number<std::uint64_t>();  // message end time
      const std::uint64_t size = f.number<std::uint64_t>();
      const std::uint32_t crc = f.number<std::uint32_t>();
      const std::string compression = f.string();
      const std::uint64_t stored = f.number<std::uint64_t>();
      const std::span<const std::uint8_t> data{f.take(stored), static_cast<std::size_t>(stored)};
      if (size > kMaxRecordBytes) throw Malformed("it expands to more than 256 MB");
      records = decompress(compression, data, static_cast<std::size_t>(size));
      if (crc != 0 && crc32(0, records.data(), static_cast<uInt>(records.size())) != crc)
        throw Malformed("its CRC does not match its records");
      // Validate every inner record before handing any on, so a damaged chunk is skipped whole.
      for (std::size_t at = 0; at < records.size();) {
        if (records.size() - at < 9) throw Malformed("a record header runs past the chunk");
        const std::uint64_t len = le64(records.data() + at + 1);
        if (len > records.size() - at - 9) throw Malformed("a record runs past the chunk");
        at += 9 + static_cast<std::size_t>(len);
      }
    } catch (const Malformed& e) {
      damaged("the chunk at byte " + std::to_string(offset) + ": " + e.what());
      return false;
    }
    for (std::size_t at = 0; at < records.size();) {
      const std::uint64_t len = le64(records.data() + at + 1);
      try {
        record(records[at], {records.data() + at + 9, static_cast<std::size_t>(len)}, offset);
      } catch (const Malformed& e) {
        throw InputError(name_ + ": the chunk at byte " + std::to_string(offset) + ": " + e.what());
      }
      at += 9 + static_cast<std::size_t>(len);
    }
    return true;
  }

  ReadReport run(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(name_ + ": cannot open");
    std::error_code ec;
    report_.file_bytes = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(name_ + ": " + ec.message());
    char magic[8];
    if (!in.read(magic, 8) || std::memcmp(magic, kMagic, 8) != 0)
      throw InputError(name_ + ": not an MCAP file (it does not start with the MCAP magic bytes)");
    read_summary(in);
    jump(in, 8);
    while (next_record(in)) {
    }
    return report_;
  }

 private:
  // Reads the record at at_ and moves past it; false at the end of the data section (or of what is left of it).
  bool next_record(std::ifstream& in) {
    report_.read_bytes = at_;
    std::uint8_t head[9];
    if (report_.file_bytes - at_ < 9 || !in.read(reinterpret_cast<char*>(head), 9)) {
      if (whole_) {  // past the data section's end without DataEnd: only after resuming at the file's end
        if (at_ < report_.file_bytes)
          damaged("byte " + std::to_string(at_) + ": the data section ends without DataEnd");
        return false;
      }
      report_.truncated = true;  // no DataEnd or Footer: cut short
      return false;
    }
    const std::uint64_t len = le64(head + 1);
    const std::uint8_t op = head[0];
    if (len > report_.file_bytes - at_ - 9 && whole_) {
      damaged("byte " + std::to_string(at_) + ": a record of " + std::to_string(len) +
              " bytes runs past the end of the file, which is whole (it ends with the MCAP footer)");
      jump(in, resume_after(at_));
      return true;
    }
    if (chunks_.count(at_) && op != kChunk) {
      damaged("byte " + std::to_string(at_) + ": the summary lists a chunk here, but the record is not one (opcode " +
              std::to_string(op) + ")");
      jump(in, resume_after(at_));
      return true;
    }
    if (len > report_.file_bytes - at_ - 9) {
      report_.truncated = true;
      if (op == kChunk) {
        bytes_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(report_.file_bytes - at_ - 9,
                                                                       kMaxRecordBytes)));
        if (in.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(bytes_.size())))
          cut_chunk(bytes_, at_);
      }
      return false;
    }
    if (op == kDataEnd || op == kFooter) return false;
    if (op != kChunk && op != kSchema && op != kChannel && op != kMessage) {
      in.seekg(static_cast<std::streamoff>(len), std::ios::cur);
      at_ += 9 + len;
      return true;
    }
    if (len > kMaxRecordBytes + 64)
      throw InputError(name_ + ": byte " + std::to_string(at_) + ": a record of " + std::to_string(len) +
                       " bytes (more than 256 MB)");
    bytes_.resize(static_cast<std::size_t>(len));
    if (!in.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(len)))
      throw InputError(name_ + ": byte " + std::to_string(at_) + ": cannot read the record");
    if (op == kChunk) {
      if (!chunk(bytes_, at_) && !chunks_.empty()) {  // skipped: resume at the next chunk the summary knows
        jump(in, resume_after(at_));
        return true;
      }
    } else {
      try {
        record(op, bytes_, at_);
      } catch (const Malformed& e) {
        throw InputError(name_ + ": byte " + std::to_string(at_) + ": " + e.what());
      }
    }
    at_ += 9 + len;
    return true;
  }

  void jump(std::ifstream& in, std::uint64_t to) {
    at_ = to;
    in.clear();
    in.seekg(static_cast<std::streamoff>(at_));
  }

  void damaged(const std::string& what) {
    if (!skip_damaged_) throw InputError(name_ + ": " + what + " (skip_damaged skips the damaged part)");
    if (report_.damaged_chunks++ == 0) report_.first_damage = what;
  }

  // A file that ends with its footer and the magic is whole: a record running past its end, or a chunk the summary
  // lists that cannot be read, is damage, not a cut. Reads the summary's chunk index (the chunks' offsets), with
  // which reading resumes after damage.
  void read_summary(std::ifstream& in) {
    if (report_.file_bytes < 8 + 9 + 20 + 8) return;
    std::uint8_t tail[9 + 20 + 8];
    in.seekg(static_cast<std::streamoff>(report_.file_bytes - sizeof tail));
    if (!in.read(reinterpret_cast<char*>(tail), sizeof tail) || std::memcmp(tail + 29, kMagic, 8) != 0 ||
        tail[0] != kFooter || le64(tail + 1) != 20)
      return;
    whole_ = true;
    const std::uint64_t footer = report_.file_bytes - sizeof tail, summary = le64(tail + 9);
    if (summary < 8 || summary >= footer || footer - summary > kMaxRecordBytes) return;
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(footer - summary));
    in.seekg(static_cast<std::streamoff>(summary));
    if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()))) return;
    for (std::size_t at = 0; bytes.size() - at >= 9;) {
      const std::uint64_t len = le64(bytes.data() + at + 1);
      if (len > bytes.size() - at - 9) break;
      if (bytes[at] == kChunkIndex && len >= 24) chunks_.insert(le64(bytes.data() + at + 9 + 16));
      at += 9 + static_cast<std::size_t>(len);
    }
  }

  // After damage at `at`: the next chunk the summary lists, or the file's end when there is none.
  std::uint64_t resume_after(std::uint64_t at) const {
    const auto next = chunks_.upper_bound(at);
    return next == chunks_.end() ? report_.file_bytes : *next;
  }

  // The records of the chunk the file was cut in: its compressed bytes up to the cut, decompressed as far as they
  // go, and every whole record in them (a recorder killed mid-write leaves its last chunk so).
  void cut_chunk(std::span<const std::uint8_t> bytes, std::uint64_t offset) {
    std::vector<std::uint8_t> records;
    try {
      Fields f{bytes};
      f.number<std::uint64_t>();
      f.number<std::uint64_t>();
      const std::uint64_t size = f.number<std::uint64_t>();
      f.number<std::uint32_t>();
      const std::string compression = f.string();
      f.number<std::uint64_t>();
      if (size > kMaxRecordBytes) return;
      records = decompress_prefix(compression, f.rest(), static_cast<std::size_t>(size));
    } catch (const Malformed&) {
      return;  // the cut came before the chunk's data
    }
    for (std::size_t at = 0; records.size() - at >= 9;) {
      const std::uint64_t len = le64(records.data() + at + 1);
      if (len > records.size() - at - 9) break;
      try {
        record(records[at], {records.data() + at + 9, static_cast<std::size_t>(len)}, offset);
      } catch (const Malformed& e) {
        throw InputError(name_ + ": the chunk at byte " + std::to_string(offset) + ": " + e.what());
      }
      ++report_.cut_chunk_records;
      at += 9 + static_cast<std::size_t>(len);
    }
  }

  // As much of a compressed stream's output as its first bytes give (none when they do not decompress).
  static std::vector<std::uint8_t> decompress_prefix(const std::string& compression,
                                                     std::span<const std::uint8_t> data, std::size_t size) {
    std::vector<std::uint8_t> out(size);
    std::size_t produced = 0;
    if (compression.empty()) {
      produced = std::min(size, data.size());
      if (produced > 0) std::memcpy(out.data(), data.data(), produced);
    } else if (compression == "zstd") {
      const std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
      ZSTD_inBuffer in{data.data(), data.size(), 0};
      ZSTD_outBuffer o{out.data(), out.size(), 0};
      while (in.pos < in.size && o.pos < o.size) {
        const std::size_t before = in.pos + o.pos;
        if (ZSTD_isError(ZSTD_decompressStream(ctx.get(), &o, &in)) || in.pos + o.pos == before) break;
      }
      produced = o.pos;
    } else if (compression == "lz4") {
      LZ4F_dctx* raw = nullptr;
      if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION))) return {};
      const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw,
                                                                                      LZ4F_freeDecompressionContext);
      std::size_t consumed = 0;
      while (consumed < data.size() && produced < out.size()) {
        std::size_t dst = out.size() - produced, src = data.size() - consumed;
        const std::size_t hint = LZ4F_decompress(ctx.get(), out.data() + produced, &dst, data.data() + consumed, &src,
                                                 nullptr);
        if (LZ4F_isError(hint)) break;
        produced += dst, consumed += src;
        if (hint == 0 || (dst == 0 && src == 0)) break;
      }
    }
    out.resize(produced);
    return out;
  }

  static std::vector<std::uint8_t> decompress(const std::string& compression, std::span<const std::uint8_t> data,
                                              std::size_t size) {
    std::vector<std::uint8_t> out(size);
    if (compression.empty()) {
      if (data.size() != size) throw Malformed("its uncompressed records are not the size it states");
      if (size > 0) std::memcpy(out.data(), data.data(), size);
    } else if (compression == "zstd") {
      const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
      if (ZSTD_isError(n)) throw Malformed(std::string("zstd: ") + ZSTD_getErrorName(n));
      if (n != size) throw Malformed("its zstd data does not expand to the size it states");
    } else if (compression == "lz4") {
      LZ4F_dctx* ctx = nullptr;
      if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) throw Malformed("lz4: out of memory");
      const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> owner(ctx,
                                                                                        LZ4F_freeDecompressionContext);
      std::size_t produced = 0, consumed = 0;
      while (consumed < data.size()) {
        std::size_t dst = out.size() - produced, src = data.size() - consumed;
        const std::size_t hint = LZ4F_decompress(ctx, out.data() + produced, &dst, data.data() + consumed, &src,
                                                 nullptr);
        if (LZ4F_isError(hint)) throw Malformed(std::string("lz4: ") + LZ4F_getErrorName(hint));
        produced += dst, consumed += src;
        if (hint == 0) break;
        if (dst == 0 && src == 0) throw Malformed("lz4: its data expands past the size it states");
      }
      if (produced != size) throw Malformed("its lz4 data does not expand to the size it states");
    } else {
      throw Malformed("compression '" + compression + "' (this reader knows none, lz4 and zstd)");
    }
    return out;
  }

  std::string name_;
  const MessageHandler& on_message_;
  bool skip_damaged_;
  std::map<std::uint16_t, Schema> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  ReadReport report_;
  std::uint64_t at_ = 0;              // where the record being read starts
  std::vector<std::uint8_t> bytes_;   // its bytes
  bool whole_ = false;                // the file ends with its footer and magic
  std::set<std::uint64_t> chunks_;    // the chunks' offsets, from the summary's chunk index
};

}  // namespace

bool has_mcap_magic(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8];
  return in.read(magic, 8) && std::memcmp(magic, kMagic, 8) == 0;
}

ReadReport read_messages(const std::filesystem::path& path, const MessageHandler& on_message, bool skip_damaged) {
  return Reader(path, on_message, skip_damaged).run(path);
}

}  // namespace partslam::io::mcap
