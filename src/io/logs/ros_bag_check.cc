// rosbag_messages::check_bag_structure: the ROS bag 2.0 file format (http://wiki.ros.org/Bags/Format/2.0) walked
// the way librosbag reads it, before librosbag sees the file. librosbag trusts every length and offset in a bag: a
// record header of 2^32 - 1 bytes made it allocate 4 GB, and an index entry pointing past its chunk made it read
// beyond its buffer (fuzz_ros_bag). This walk checks each of them against the file and the chunks' contents. It
// needs no ROS headers (C++20); it reads the file piecewise and decompresses each chunk (bz2, lz4) once more to check
// the message offsets, so a bag costs about twice its reading time. walk_bag_chunks reads the records one after the
// other, for bags cut short (whose index, written last, is gone) or damaged (resuming after a damaged record at the
// next chunk the index lists, when it reads whole).
#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/logs/ros_bag_check.h"

namespace partslam::io::rosbag_messages {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint8_t kOpMessage = 0x02, kOpBagHeader = 0x03, kOpIndex = 0x04, kOpChunk = 0x05,
                       kOpChunkInfo = 0x06, kOpConnection = 0x07;

[[noreturn]] void fail(const std::string& what) { throw BagError("not a readable ROS 1 bag (" + what + ")"); }

std::uint32_t u32(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);  // little-endian, as bags are
  return v;
}

std::uint64_t u64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}

// "name=value" fields of a record header (or of a connection header), each preceded by its length.
using Fields = std::map<std::string, std::string, std::less<>>;

Fields parse_fields(const std::uint8_t* p, std::size_t size, const char* what) {
  Fields fields;
  while (size > 0) {
    if (size < 4) fail(std::string(what) + ": a field length cut short");
    const std::uint32_t n = u32(p);
    p += 4, size -= 4;
    if (n > size) fail(std::string(what) + ": a field longer than its header");
    const std::string_view field(reinterpret_cast<const char*>(p), n);
    const std::size_t eq = field.find('=');
    if (eq == std::string_view::npos) fail(std::string(what) + ": a field without '='");
    fields.emplace(std::string(field.substr(0, eq)), std::string(field.substr(eq + 1)));
    p += n, size -= n;
  }
  return fields;
}

// Where records are read from: the bag file (read piecewise: bags can be gigabytes) or a chunk's contents.
class Source {
 public:
  virtual ~Source() = default;
  virtual std::uint64_t size() const = 0;
  /// Bytes [pos, pos + n), which the caller has checked lie within size().
  virtual std::vector<std::uint8_t> read(std::uint64_t pos, std::size_t n) = 0;
};

class FileSource : public Source {
 public:
  explicit FileSource(const std::string& path) : in_(path, std::ios::binary | std::ios::ate) {
    if (!in_) throw BagError("cannot open");
    size_ = static_cast<std::uint64_t>(in_.tellg());
  }
  std::uint64_t size() const override { return size_; }
  std::vector<std::uint8_t> read(std::uint64_t pos, std::size_t n) override {
    std::vector<std::uint8_t> out(n);
    in_.seekg(static_cast<std::streamoff>(pos));
    in_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
    if (static_cast<std::size_t>(in_.gcount()) != n) fail("a read error");
    return out;
  }

 private:
  std::ifstream in_;
  std::uint64_t size_ = 0;
};

// A chunk's uncompressed records. Not zero-filled when allocated: a hostile chunk claiming kMaxChunkBytes costs
// only the pages its data fills, not a memset of kMaxChunkBytes each (docs/NOTES.md, "Fuzzing and sanitizers").
struct ChunkBytes {
  std::unique_ptr<std::uint8_t[]> data;
  std::size_t size = 0;
};

class BufferSource : public Source {
 public:
  explicit BufferSource(const ChunkBytes& bytes) : bytes_(bytes) {}
  std::uint64_t size() const override { return bytes_.size; }
  std::vector<std::uint8_t> read(std::uint64_t pos, std::size_t n) override {
    return {bytes_.data.get() + pos, bytes_.data.get() + pos + n};
  }

 private:
  const ChunkBytes& bytes_;
};

// Longest record header, and connection header, read [bytes]: real ones hold a few fields and a message definition.
constexpr std::uint32_t kMaxHeaderBytes = 16u << 20;

// A record: its header fields and where its data lies in its source.
struct Record {
  Fields fields;
  std::uint64_t data = 0;  ///< position of the data
  std::uint32_t data_len = 0;
  std::uint64_t end = 0;   ///< position just past the record
};

Record read_record(Source& source, std::uint64_t pos, const char* what) {
  const std::uint64_t size = source.size();
  const std::string where = std::string(what) + " at " + std::to_string(pos);
  if (pos > size || size - pos < 4) fail(where + ": past the end");
  const std::uint32_t header_len = u32(source.read(pos, 4).data());
  if (header_len > size - pos - 4 || size - pos - 4 - header_len < 4) fail(where + ": header longer than what follows");
  if (header_len > kMaxHeaderBytes) fail(where + ": header of more than 16 MB");
  Record r;
  const std::vector<std::uint8_t> header = source.read(pos + 4, header_len);
  r.fields = parse_fields(header.data(), header.size(), what);
  r.data_len = u32(source.read(pos + 4 + header_len, 4).data());
  r.data = pos + 8 + header_len;
  if (r.data_len > size - r.data) fail(where + ": data longer than what follows");
  r.end = r.data + r.data_len;
  return r;
}

const std::string& field(const Record& r, const char* name, std::size_t size, const char* what) {
  const auto it = r.fields.find(name);
  if (it == r.fields.end()) fail(std::string(what) + ": no '" + name + "' field");
  if (size != 0 && it->second.size() != size) fail(std::string(what) + ": field '" + name + "' of the wrong size");
  return it->second;
}

void require_op(const Record& r, std::uint8_t op, const char* what) {
  const std::string& value = field(r, "op", 1, what);
  if (static_cast<std::uint8_t>(value[0]) != op) fail(std::string(what) + ": wrong record type");
}

std::uint32_t field_u32(const Record& r, const char* name, const char* what) {
  return u32(reinterpret_cast<const std::uint8_t*>(field(r, name, 4, what).data()));
}

std::uint64_t field_u64(const Record& r, const char* name, const char* what) {
  return u64(reinterpret_cast<const std::uint8_t*>(field(r, name, 8, what).data()));
}

// A bag time (sec, nsec: two little-endian u32) as librosbag reads it: ros::Time normalises nsec into sec and
// throws a bare std::runtime_error ("Time is out of dual 32-bit range") when sec + nsec / 1e9 passes 2^32 - 1.
// Checked here, so the bag is refused as damaged, naming where, before librosbag sees it (fuzz_ros_bag).
void check_time(const std::uint8_t* p, const std::string& where) {
  const std::uint64_t sec = u32(p), nsec = u32(p + 4);
  if (sec + nsec / 1000000000u > 0xffffffffu)
    fail(where + ": a time out of ROS's range (sec " + std::to_string(sec) + ", nsec " + std::to_string(nsec) + ")");
}

void check_time_field(const Record& r, const char* name, const char* what, const std::string& where) {
  check_time(reinterpret_cast<const std::uint8_t*>(field(r, name, 8, what).data()),
             where + ", field '" + name + "'");
}

// The uncompressed records of a chunk.
ChunkBytes chunk_contents(Source& file, const Record& chunk) {
  const std::string& compression = field(chunk, "compression", 0, "chunk");
  const std::uint32_t size = field_u32(chunk, "size", "chunk");
  if (size > kMaxChunkBytes || chunk.data_len > kMaxChunkBytes)
    fail("a chunk of more than " + std::to_string(kMaxChunkBytes) + " bytes");
  ChunkBytes out{std::unique_ptr<std::uint8_t[]>(new std::uint8_t[std::max<std::uint32_t>(size, 1)]), size};
  const std::vector<std::uint8_t> data = file.read(chunk.data, chunk.data_len);
  const auto* in = reinterpret_cast<const char*>(data.data());
  if (compression == "none") {
    if (chunk.data_len != size) fail("an uncompressed chunk whose size disagrees with its data");
    if (size > 0) std::memcpy(out.data.get(), in, size);  // an empty chunk's data is no buffer at all
  } else if (compression == "bz2") {
    unsigned int got = size;
    if (BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data.get()), &got, const_cast<char*>(in), chunk.data_len,
                                   0, 0) != BZ_OK ||
        got != size)
      fail("a bz2 chunk that does not decompress to its size");
  } else if (compression == "lz4") {
    unsigned int got = size;
    if (roslz4_buffToBuffDecompress(const_cast<char*>(in), chunk.data_len, reinterpret_cast<char*>(out.data.get()),
                                    &got) != ROSLZ4_OK ||
        got != size)
      fail("an lz4 chunk that does not decompress to its size");
  } else {
    fail("chunk compression '" + compression.substr(0, 20) + "' (expected none, bz2 or lz4)");
  }
  return out;
}

// The bag header: checks the magic line and returns the record (its data is padding).
Record read_bag_header(Source& file) {
  const std::size_t head = static_cast<std::size_t>(std::min<std::uint64_t>(file.size(), kMagic.size()));
  const std::vector<std::uint8_t> magic = file.read(0, head);
  if (head < kMagic.size() || std::memcmp(magic.data(), kMagic.data(), kMagic.size()) != 0) {
    if (head >= 9 && std::memcmp(magic.data(), "#ROSBAG V", 9) == 0)
      fail("bag format other than 2.0: only ROS bag format 2.0 is read");
    fail("no '#ROSBAG V2.0' line");
  }
  const Record header = read_record(file, kMagic.size(), "bag header");
  require_op(header, kOpBagHeader, "bag header");
  return header;
}

}  // namespace

void check_bag_structure(const std::string& path) {
  FileSource file(path);
  const Record header = read_bag_header(file);
  const std::uint64_t index_pos = field_u64(header, "index_pos", "bag header");
  const std::uint32_t connections = field_u32(header, "conn_count", "bag header");
  const std::uint32_t chunks = field_u32(header, "chunk_count", "bag header");
  if (index_pos == 0) fail("unindexed: the recording was interrupted; 'rosbag reindex' it");
  if (index_pos < header.end || index_pos >= file.size()) fail("index position outside the file");

  // The index section: the connection records, then a chunk info record per chunk.
  std::uint64_t pos = index_pos;
  for (std::uint32_t i = 0; i < connections; ++i) {
    const Record r = read_record(file, pos, "connection record");
    require_op(r, kOpConnection, "connection record");
    field(r, "conn", 4, "connection record");
    field(r, "topic", 0, "connection record");
    if (r.data_len > kMaxHeaderBytes) fail("connection record: header of more than 16 MB");
    const std::vector<std::uint8_t> connection_header = file.read(r.data, r.data_len);
    parse_fields(connection_header.data(), connection_header.size(), "connection header");
    pos = r.end;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> chunk_infos;  // chunk position, connections in it
  for (std::uint32_t i = 0; i < chunks; ++i) {
    const Record r = read_record(file, pos, "chunk info record");
    require_op(r, kOpChunkInfo, "chunk info record");
    if (field_u32(r, "ver", "chunk info record") != 1) fail("chunk info version other than 1");
    const std::string where = "chunk info record at " + std::to_string(pos);
    check_time_field(r, "start_time", "chunk info record", where);
    check_time_field(r, "end_time", "chunk info record", where);
    const std::uint32_t count = field_u32(r, "count", "chunk info record");
    if (r.data_len != std::uint64_t{count} * 8) fail("chunk info record: data size disagrees with its count");
    chunk_infos.emplace_back(field_u64(r, "chunk_pos", "chunk info record"), count);
    pos = r.end;
  }

  // Each chunk, and the index data records after it, whose entries must point at message records in the chunk.
  for (const auto& [chunk_pos, index_records] : chunk_infos) {
    if (chunk_pos >= file.size()) fail("chunk position outside the file");
    const Record chunk = read_record(file, chunk_pos, "chunk");
    require_op(chunk, kOpChunk, "chunk");
    const ChunkBytes contents = chunk_contents(file, chunk);
    BufferSource records(contents);
    std::uint64_t next = chunk.end;
    for (std::uint32_t i = 0; i < index_records; ++i) {
      const Record index = read_record(file, next, "index data record");
      require_op(index, kOpIndex, "index data record");
      if (field_u32(index, "ver", "index data record") != 1) fail("index data version other than 1");
      field(index, "conn", 4, "index data record");
      const std::uint32_t count = field_u32(index, "count", "index data record");
      if (index.data_len != std::uint64_t{count} * 12) fail("index data record: data size disagrees with its count");
      const std::vector<std::uint8_t> entries = file.read(index.data, index.data_len);
      for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint8_t* entry = &entries[12 * std::size_t{k}];
        check_time(entry, "index data record at " + std::to_string(next) + ", entry " + std::to_string(k));
        const std::uint32_t offset = u32(entry + 8);
        const Record message = read_record(records, offset, "message data record");
        require_op(message, kOpMessage, "message data record");
        field(message, "conn", 4, "message data record");
        check_time_field(message, "time", "message data record",
                         "message data record at " + std::to_string(offset) + " of the chunk at " +
                             std::to_string(chunk_pos));
      }
      next = index.end;
    }
  }
}

namespace {

// The text inside "not a readable ROS 1 bag (...)".
std::string problem_of(const BagError& e) {
  std::string_view what = e.what();
  constexpr std::string_view kPrefix = "not a readable ROS 1 bag (";
  if (what.starts_with(kPrefix) && what.ends_with(")")) what = what.substr(kPrefix.size(), what.size() - kPrefix.size() - 1);
  return std::string(what);
}

// Whether the record at pos runs past the end of the source (or its length fields do).
bool runs_past_end(Source& source, std::uint64_t pos) {
  const std::uint64_t size = source.size();
  if (size - pos < 8) return true;
  const std::uint32_t header_len = u32(source.read(pos, 4).data());
  if (header_len > size - pos - 8) return true;
  const std::uint32_t data_len = u32(source.read(pos + 4 + header_len, 4).data());
  return data_len > size - pos - 8 - header_len;
}

class Walker {
 public:
  Walker(const std::vector<std::string>& keep, std::size_t max_bytes, ChunkWalk& out)
      : keep_(keep), max_bytes_(max_bytes), out_(out) {}

  void connection(Source& source, const Record& r) {
    const std::uint32_t id = field_u32(r, "conn", "connection record");
    if (r.data_len > kMaxHeaderBytes) fail("connection record: header of more than 16 MB");
    const std::vector<std::uint8_t> bytes = source.read(r.data, r.data_len);
    const Fields header = parse_fields(bytes.data(), bytes.size(), "connection header");
    const auto get = [&header](const char* name) {
      const auto it = header.find(name);
      return it == header.end() ? std::string() : it->second;
    };
    BagConnection c{field(r, "topic", 0, "connection record"), get("type"), get("md5sum")};
    const auto same = [&c](const BagConnection& o) {
      return o.topic == c.topic && o.datatype == c.datatype && o.md5sum == c.md5sum;
    };
    const auto it = std::find_if(out_.connections.begin(), out_.connections.end(), same);
    connections_[id] = static_cast<std::size_t>(it - out_.connections.begin());
    if (it == out_.connections.end()) {
      if (out_.connections.size() >= 4096) fail("more than 4096 different connections");
      out_.connections.push_back(std::move(c));
    }
  }

  void message(Source& source, const Record& r, std::uint64_t position, std::vector<RawMessage>& to) {
    const auto it = connections_.find(field_u32(r, "conn", "message data record"));
    if (it == connections_.end()) fail("message data record: a connection not defined before it");
    const std::string& time = field(r, "time", 8, "message data record");
    const std::string& datatype = out_.connections[it->second].datatype;
    if (std::find(keep_.begin(), keep_.end(), datatype) == keep_.end()) return;
    bytes_ += std::size_t{r.data_len} + 64;  // 64: what a message costs besides its data
    if (bytes_ > max_bytes_) throw BagError("more than " + std::to_string(max_bytes_) + " bytes of messages");
    RawMessage m{it->second, 0, position, source.read(r.data, r.data_len)};
    const auto* t = reinterpret_cast<const std::uint8_t*>(time.data());
    m.time = std::uint64_t{u32(t)} << 32 | u32(t + 4);
    to.push_back(std::move(m));
  }

  // The records of a chunk: connections and messages, all or none.
  void chunk(Source& file, const Record& r, std::uint64_t position) {
    require_op(r, kOpChunk, "chunk");
    const ChunkBytes contents = chunk_contents(file, r);
    BufferSource records(contents);
    std::vector<RawMessage> messages;
    const auto saved = connections_;
    try {
      for (std::uint64_t pos = 0; pos < contents.size;) {
        const Record inner = read_record(records, pos, "record in the chunk");
        const std::uint8_t op = static_cast<std::uint8_t>(field(inner, "op", 1, "record in the chunk")[0]);
        if (op == kOpConnection) connection(records, inner);
        else if (op == kOpMessage) message(records, inner, position, messages);
        else fail("a record of type " + std::to_string(op) + " in a chunk");
        pos = inner.end;
      }
    } catch (const BagError&) {
      connections_ = saved;
      throw;
    }
    for (RawMessage& m : messages) out_.messages.push_back(std::move(m));
    ++out_.chunks;
  }

  void top_level_message(Source& file, const Record& r, std::uint64_t position) {
    message(file, r, position, out_.messages);
  }

 private:
  const std::vector<std::string>& keep_;
  const std::size_t max_bytes_;
  ChunkWalk& out_;
  std::map<std::uint32_t, std::size_t> connections_;  ///< connection id -> index in out_.connections
  std::size_t bytes_ = 0;
};

}  // namespace

namespace {

// The bag's index (connection records, then a chunk info record per chunk, at the header's index_pos), when it
// reads whole: its connection records and the positions of its chunks, sorted. nullopt when the bag was never
// closed (index_pos 0), the file ends before index_pos, or any index record is malformed. Bounded by the file:
// every record read lies within it.
struct BagIndex {
  std::vector<Record> connections;
  std::vector<std::uint64_t> chunk_positions;
};

std::optional<BagIndex> read_index(Source& file, const Record& header, std::uint64_t index_pos) {
  if (index_pos == 0 || index_pos < header.end || index_pos >= file.size()) return std::nullopt;
  try {
    const std::uint32_t connections = field_u32(header, "conn_count", "bag header");
    const std::uint32_t chunks = field_u32(header, "chunk_count", "bag header");
    BagIndex index;
    std::uint64_t pos = index_pos;
    for (std::uint32_t i = 0; i < connections; ++i) {
      Record r = read_record(file, pos, "connection record");
      require_op(r, kOpConnection, "connection record");
      pos = r.end;
      index.connections.push_back(std::move(r));
    }
    for (std::uint32_t i = 0; i < chunks; ++i) {
      const Record r = read_record(file, pos, "chunk info record");
      require_op(r, kOpChunkInfo, "chunk info record");
      const std::uint64_t chunk_pos = field_u64(r, "chunk_pos", "chunk info record");
      if (chunk_pos < header.end || chunk_pos >= index_pos) fail("chunk info record: a chunk outside the chunks");
      index.chunk_positions.push_back(chunk_pos);
      pos = r.end;
    }
    std::sort(index.chunk_positions.begin(), index.chunk_positions.end());
    index.chunk_positions.erase(std::unique(index.chunk_positions.begin(), index.chunk_positions.end()),
                                index.chunk_positions.end());
    return index;
  } catch (const BagError&) {
    return std::nullopt;
  }
}

// Without a readable index, the next chunk after a damaged record whose lengths cannot be trusted: the first
// record after `after` that reads as a chunk record as rosbag writes them (header fields compression, op = 0x05,
// size, in that order), found by its op field. Reads the file in blocks (the last one kept for the next call);
// examines at most 4096 op fields over all calls.
class ChunkFinder {
 public:
  explicit ChunkFinder(Source& file) : file_(file) {}

  /// The position of the next chunk record after `after`; 0 when there is none.
  std::uint64_t next_after(std::uint64_t after) {
    static constexpr std::array<std::uint8_t, 8> kOpField{4, 0, 0, 0, 'o', 'p', '=', kOpChunk};
    for (std::uint64_t from = after + 1; from < file_.size();) {
      if (from < block_at_ || from >= block_at_ + block_.size()) {
        block_at_ = from;
        block_ = file_.read(from, static_cast<std::size_t>(std::min<std::uint64_t>(kBlock, file_.size() - from)));
      }
      const auto begin = block_.begin() + static_cast<std::ptrdiff_t>(from - block_at_);
      const auto hit = std::search(begin, block_.end(), kOpField.begin(), kOpField.end());
      if (hit == block_.end()) {
        const std::uint64_t end = block_at_ + block_.size();
        if (end >= file_.size()) return 0;
        from = std::max(from + 1, end - (kOpField.size() - 1));  // a match across two blocks is found in the next
        continue;
      }
      if (matches_left_ == 0) return 0;  // a hostile file full of op fields: give up
      --matches_left_;
      const std::uint64_t op = block_at_ + static_cast<std::uint64_t>(hit - block_.begin());
      for (const std::uint64_t before : {std::uint64_t{0}, std::uint64_t{19}, std::uint64_t{20}}) {
        // the fields before op: none, "compression=bz2" / "=lz4", "compression=none" (each with its length)
        if (op < after + 1 + 4 + before) continue;
        if (is_chunk_record(op - 4 - before)) return op - 4 - before;
      }
      from = op + 1;
    }
    return 0;
  }

 private:
  static constexpr std::size_t kBlock = 1u << 20;

  bool is_chunk_record(std::uint64_t pos) {
    if (file_.size() - pos < 8 || u32(file_.read(pos, 4).data()) > 4096) return false;
    try {
      const Record r = read_record(file_, pos, "chunk");
      require_op(r, kOpChunk, "chunk");
      return r.fields.contains("compression") && r.fields.contains("size");
    } catch (const BagError&) {
      return false;
    }
  }

  Source& file_;
  std::size_t matches_left_ = 4096;  ///< op fields examined, over all calls (a real bag's are its chunks')
  std::vector<std::uint8_t> block_;
  std::uint64_t block_at_ = 0;
};

// Most resynchronisations by ChunkFinder in one walk: each may decompress a (hostile) chunk of up to
// kMaxChunkBytes that overlaps the one before, so their number is bounded; past it the rest is given up.
constexpr std::size_t kMaxScans = 64;

}  // namespace

ChunkWalk walk_bag_chunks(const std::string& path, const std::vector<std::string>& keep_types, bool skip_damaged,
                          std::size_t max_bytes) {
  FileSource file(path);
  ChunkWalk out;
  out.file_size = file.size();
  const Record header = read_bag_header(file);
  out.index_pos = field_u64(header, "index_pos", "bag header");
  Walker walker(keep_types, max_bytes, out);
  // A bag closed with its index (index_pos within the file) ends after its chunks: a record before index_pos that
  // runs past the end of the file is damage, not a cut.
  const bool closed = out.index_pos != 0 && out.index_pos >= header.end && out.index_pos < file.size();
  const std::optional<BagIndex> index = read_index(file, header, out.index_pos);
  if (index) {
    out.indexed_chunks = index->chunk_positions.size();
    for (const Record& r : index->connections) {
      try {
        walker.connection(file, r);  // so that the chunks after a damaged one holding them can be read
      } catch (const BagError&) {
        // a connection header that does not parse: its chunk's connection record may still define it
      }
    }
  }
  // With the index: the next chunk it knows after pos, or the index itself.
  const auto next_known = [&](std::uint64_t pos) {
    const auto it = std::upper_bound(index->chunk_positions.begin(), index->chunk_positions.end(), pos);
    return it == index->chunk_positions.end() ? out.index_pos : *it;
  };
  ChunkFinder finder(file);
  std::size_t scans = 0;
  const std::uint64_t end = index ? out.index_pos : file.size();  // a readable index was read above
  for (std::uint64_t pos = header.end; pos < end;) {
    std::uint64_t next = 0;
    try {
      if (runs_past_end(file, pos)) {
        if (!closed || pos >= out.index_pos) {
          out.cut_at = pos;
          break;
        }
        fail("its length runs past the end of the file at byte " + std::to_string(file.size()) +
             ", before the bag's index at byte " + std::to_string(out.index_pos));
      }
      const Record r = read_record(file, pos, "record");
      next = r.end;  // the lengths are within the file: the next record is found even when this one is damaged
      if (index && r.end > next_known(pos)) {
        next = 0;
        fail("its length runs over the chunk at byte " + std::to_string(next_known(pos)) + " (from the index)");
      }
      const std::uint8_t op = static_cast<std::uint8_t>(field(r, "op", 1, "record")[0]);
      if (op == kOpChunk) walker.chunk(file, r, pos);
      else if (op == kOpConnection) walker.connection(file, r);
      else if (op == kOpMessage) walker.top_level_message(file, r, pos);  // an unfinished uncompressed chunk's
      else if (op != kOpIndex && op != kOpChunkInfo) fail("a record of type " + std::to_string(op));
    } catch (const BagError& e) {
      if (std::string_view(e.what()).starts_with("more than ")) throw;  // the size limit, not damage
      const std::string what = "the record at byte " + std::to_string(pos) + " is damaged: " + problem_of(e);
      if (!skip_damaged) throw BagError("not a readable ROS 1 bag (" + what + "); skip_damaged skips it and reads the rest");
      if (out.damaged++ == 0) out.first_damage = what;
      if (index) {
        next = next_known(pos);  // resynchronised at the next chunk the index gives
      } else if (next == 0) {    // its lengths cannot be trusted: look for the next chunk record
        next = ++scans <= kMaxScans ? finder.next_after(pos) : 0;
        if (next == 0) {
          out.lost_at = pos;
          break;
        }
      }
    }
    pos = next;
  }
  return out;
}

}  // namespace partslam::io::rosbag_messages
