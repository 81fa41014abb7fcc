#include "io/logs/mcap_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <fstream>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io::mcap {
namespace {

using ::testing::HasSubstr;
using Bytes = std::vector<std::uint8_t>;

// A small MCAP writer for the tests (the real files in ../shared and those of tests/ros2 come from Foxglove's).
struct Out {
  Bytes b;
  template <typename T>
  Out& n(T v) {
    for (std::size_t i = 0; i < sizeof(T); ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    return *this;
  }
  Out& s(const std::string& v) {
    n<std::uint32_t>(static_cast<std::uint32_t>(v.size()));
    b.insert(b.end(), v.begin(), v.end());
    return *this;
  }
  Out& bytes(const Bytes& v) {
    b.insert(b.end(), v.begin(), v.end());
    return *this;
  }
  Out& record(std::uint8_t op, const Bytes& content) {
    b.push_back(op);
    n<std::uint64_t>(content.size());
    return bytes(content);
  }
};

Bytes schema_and_channel() {
  Out o;
  o.record(0x03, Out().n<std::uint16_t>(1).s("sensor_msgs/msg/LaserScan").s("ros2msg").s("").b);
  o.record(0x04, Out().n<std::uint16_t>(5).n<std::uint16_t>(1).s("/scan").s("cdr").n<std::uint32_t>(0).b);
  return o.b;
}

Bytes message(std::uint64_t time, std::uint8_t payload) {
  return Out().record(0x05, Out().n<std::uint16_t>(5).n<std::uint32_t>(0).n(time).n(time).bytes({payload, 7}).b).b;
}

Bytes compress(const std::string& how, const Bytes& in) {
  if (how.empty()) return in;
  Bytes out;
  if (how == "zstd") {
    out.resize(ZSTD_compressBound(in.size()));
    out.resize(ZSTD_compress(out.data(), out.size(), in.data(), in.size(), 3));
  } else {
    out.resize(LZ4F_compressFrameBound(in.size(), nullptr));
    out.resize(LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr));
  }
  return out;
}

// Header, then `chunks` chunks of `per_chunk` messages each, DataEnd, a summary of one ChunkIndex per chunk (when
// indexed), Footer, magic. chunk_at gets each chunk record's offset.
Bytes file(const std::string& compression, int chunks, int per_chunk, bool indexed = false,
           std::vector<std::uint64_t>* chunk_at = nullptr) {
  Out o;
  o.bytes({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  o.record(0x01, Out().s("ros2").s("test").b);
  std::uint64_t t = 100;
  std::vector<std::uint64_t> at;
  for (int c = 0; c < chunks; ++c) {
    Out records;
    if (c == 0) records.bytes(schema_and_channel());
    for (int m = 0; m < per_chunk; ++m, ++t) records.bytes(message(t, static_cast<std::uint8_t>(t)));
    const Bytes stored = compress(compression, records.b);
    at.push_back(o.b.size());
    o.record(0x06, Out()
                       .n<std::uint64_t>(0)
                       .n<std::uint64_t>(0)
                       .n<std::uint64_t>(records.b.size())
                       .n<std::uint32_t>(static_cast<std::uint32_t>(crc32(0, records.b.data(),
                                                                          static_cast<uInt>(records.b.size()))))
                       .s(compression)
                       .n<std::uint64_t>(stored.size())
                       .bytes(stored)
                       .b);
  }
  o.record(0x0F, Out().n<std::uint32_t>(0).b);
  const std::uint64_t summary = indexed ? o.b.size() : 0;
  for (std::size_t c = 0; indexed && c < at.size(); ++c)
    o.record(0x08, Out().n<std::uint64_t>(0).n<std::uint64_t>(0).n(at[c]).n<std::uint64_t>(0).n<std::uint32_t>(0)
                       .n<std::uint64_t>(0).s(compression).n<std::uint64_t>(0).n<std::uint64_t>(0).b);
  o.record(0x02, Out().n(summary).n<std::uint64_t>(0).n<std::uint32_t>(0).b);
  o.bytes({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'});
  if (chunk_at) *chunk_at = at;
  return o.b;
}

void write(const std::filesystem::path& path, const Bytes& b) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()),
                                              static_cast<std::streamsize>(b.size()));
}

struct Got {
  std::vector<std::uint64_t> times;
  ReadReport report;
};

Got read(const std::filesystem::path& path, bool skip_damaged = false) {
  Got g;
  g.report = read_messages(
      path,
      [&](const Channel& c, std::uint64_t t, std::span<const std::uint8_t> data) {
        EXPECT_EQ(c.topic, "/scan");
        EXPECT_EQ(c.schema_name, "sensor_msgs/msg/LaserScan");
        EXPECT_EQ(c.message_encoding, "cdr");
        EXPECT_EQ(data.size(), 2u);
        EXPECT_EQ(data[0], static_cast<std::uint8_t>(t));
        g.times.push_back(t);
      },
      skip_damaged);
  return g;
}

TEST(McapFile, ReadsEveryMessageOfEveryCompression) {
  testing::TempDir dir;
  for (const std::string c : {"", "zstd", "lz4"}) {
    write(dir / "a.mcap", file(c, 3, 4));
    const Got g = read(dir / "a.mcap");
    EXPECT_EQ(g.times.size(), 12u) << c;
    EXPECT_FALSE(g.report.truncated) << c;
    EXPECT_EQ(g.report.messages, 12u);
  }
}

// Cut at every byte: no crash, a truncated report, and the messages read are a prefix of the whole file's, all
// of them once the cut passes the data section. Uncompressed chunks give back every message whose record lies
// whole before the cut.
TEST(McapFile, EveryCutReadsThePrefixBeforeIt) {
  testing::TempDir dir;
  for (const std::string c : {"", "zstd", "lz4"}) {
    const Bytes whole = file(c, 3, 4);
    std::size_t last = 0;
    for (std::size_t n = 8; n < whole.size(); ++n) {
      write(dir / "cut.mcap", Bytes(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n)));
      const Got g = read(dir / "cut.mcap");
      for (std::size_t i = 0; i < g.times.size(); ++i) ASSERT_EQ(g.times[i], 100 + i) << c << " cut " << n;
      EXPECT_GE(g.times.size(), last) << c << " cut " << n;  // a longer file never gives fewer
      last = g.times.size();
      if (g.report.truncated) {
        EXPECT_LE(g.report.read_bytes, n);
      }
    }
    EXPECT_EQ(last, 12u) << c;
  }
  // Uncompressed: a cut inside the first chunk's third message record gives the first two.
  const Bytes plain = file("", 1, 4);
  const std::size_t first_message = 8 + 9 + 16 + 9 + 8 + 8 + 8 + 4 + 4 + 8 + schema_and_channel().size();
  const std::size_t message_bytes = message(0, 0).size();
  write(dir / "cut.mcap", Bytes(plain.begin(), plain.begin() + static_cast<std::ptrdiff_t>(first_message +
                                                                                           2 * message_bytes + 5)));
  const Got g = read(dir / "cut.mcap");
  EXPECT_EQ(g.times.size(), 2u);
  EXPECT_TRUE(g.report.truncated);
}

TEST(McapFile, ADamagedChunkIsAnErrorOrSkippedAndCounted) {
  testing::TempDir dir;
  for (const std::string c : {"", "zstd", "lz4"}) {
    Bytes b = file(c, 3, 4);
    const Bytes one = file(c, 1, 4);
    // A byte of the second chunk's data flipped: the CRC (or the decompression) fails.
    const std::size_t second = one.size() - (9 + 4) - (9 + 20) - 8;  // `one` less its DataEnd, Footer and magic
    b[second + 9 + 8 + 8 + 8 + 4 + 4 + c.size() + 8 + 6] ^= 0x5a;
    write(dir / "bad.mcap", b);
    try {
      read(dir / "bad.mcap");
      ADD_FAILURE() << c << ": no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("bad.mcap: the chunk at byte " + std::to_string(second))) << c;
      EXPECT_THAT(e.what(), HasSubstr("skip_damaged"));
    }
    const Got g = read(dir / "bad.mcap", true);
    EXPECT_EQ(g.times.size(), 8u) << c;
    EXPECT_EQ(g.report.damaged_chunks, 1u) << c;
    EXPECT_THAT(g.report.first_damage, HasSubstr("chunk at byte " + std::to_string(second)));
  }
}

// A file that ends with its footer is whole: a chunk whose length runs past the end, whose opcode is damaged, or
// whose length is too short is damage, not a cut; with skip_damaged reading resumes at the next chunk the
// summary's chunk index lists, so only the damaged chunk's messages are lost.
TEST(McapFile, DamageInAWholeFileIsNotACutAndReadingResumesAfterIt) {
  testing::TempDir dir;
  std::vector<std::uint64_t> at;
  const Bytes whole = file("zstd", 3, 4, true, &at);
  const auto set_length = [&](Bytes& b, std::uint64_t len) {
    for (int i = 0; i < 8; ++i) b[at[1] + 1 + i] = static_cast<std::uint8_t>(len >> (8 * i));
  };
  Bytes past = whole, opcode = whole, shortened = whole;
  set_length(past, 1u << 30);
  opcode[at[1]] = 0x42;
  set_length(shortened, 40);
  const std::vector<std::pair<Bytes, std::string>> cases = {
      {past, "runs past the end of the file, which is whole"},
      {opcode, "the summary lists a chunk here, but the record is not one"},
      {shortened, "the chunk at byte " + std::to_string(at[1])}};
  for (const auto& [bytes, message] : cases) {
    write(dir / "d.mcap", bytes);
    try {
      read(dir / "d.mcap");
      ADD_FAILURE() << message << ": no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message));
      EXPECT_THAT(e.what(), HasSubstr("skip_damaged"));
    }
    const Got g = read(dir / "d.mcap", true);
    EXPECT_FALSE(g.report.truncated) << message;
    EXPECT_EQ(g.report.damaged_chunks, 1u) << message;
    EXPECT_EQ(g.times, (std::vector<std::uint64_t>{100, 101, 102, 103, 108, 109, 110, 111})) << message;
  }
}

TEST(McapFile, ForeignFilesAreRefusedByName) {
  testing::TempDir dir;
  write(dir / "x.mcap", Bytes{'#', 'R', 'O', 'S', 'B', 'A', 'G', ' ', 'V', '2'});
  try {
    read(dir / "x.mcap");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("x.mcap: not an MCAP file"));
  }
  EXPECT_THROW(read(dir / "absent.mcap"), InputError);
  // A message on a channel no record defined.
  Out o;
  o.bytes({0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'}).bytes(message(1, 1));
  write(dir / "orphan.mcap", o.b);
  try {
    read(dir / "orphan.mcap");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("orphan.mcap: byte 8: a message on channel 5"));
  }
}

}  // namespace
}  // namespace partslam::io::mcap
