// A ROS 1 bag whose bytes lie (io/logs/ros_bag_check.h): lengths, offsets and times that librosbag would trust,
// as fuzz_ros_bag made them, refused naming the file and the place before librosbag sees them; bags cut short or
// with damaged chunks, read up to their last whole chunk or, with skip_damaged, past the damage.
#include "io/logs/ros_bag_check.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "io/logs/ros_bag.h"
#include "io/logs/ros_bag_messages.h"
#include "io/logs/scan_source.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

// Bags whose lengths and offsets lie, as fuzz_ros_bag made them: librosbag trusted each of them (allocating up to
// 4 GB, or reading past its buffers); they are refused as not readable bags, naming the file, before it sees them.
// Three scans of three ranges each, one odometry message before each: the small good bag the damage tests spoil.
rosbag_messages::BagMessages three_scans() {
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 3; ++k) {
    m.odometry.push_back({10.0 + k, 0.1 * k, 0.0, 0.0, 0.0, 0.0, 1.0});
    m.scans.push_back({10.5 + k, -1.5, 0.5, 0.1, 30.0, {1.5f, 2.5f, 3.5f}, "laser"});
  }
  return m;
}

// Where the first entry of the first index data record (op 4) of a bag's bytes lies, found by walking the top-level
// records: an entry is a time (sec, nsec: 8 bytes) and the message's offset in its chunk (4 bytes). 0 if none.
std::size_t first_index_entry(const std::string& bag) {
  using namespace std::string_view_literals;
  for (std::size_t pos = 13; pos + 8 <= bag.size();) {
    std::uint32_t header_len = 0, data_len = 0;
    std::memcpy(&header_len, bag.data() + pos, 4);
    if (header_len > bag.size() - pos - 8) return 0;
    std::memcpy(&data_len, bag.data() + pos + 4 + header_len, 4);
    const std::size_t data = pos + 8 + header_len;
    if (std::string_view(bag.data() + pos + 4, header_len).find("op=\x04"sv) != std::string_view::npos) return data;
    pos = data + data_len;
  }
  return 0;
}

// A good bag of three_scans(), with /odom and with /tf odometry, and how a spoiled copy of it reads.
class LyingBag : public ::testing::Test {
 protected:
  void SetUp() override {
    const rosbag_messages::BagMessages m = three_scans();
    rosbag_messages::write_bag_messages((dir_ / "good.bag").string(), m, /*as_tf=*/false);
    rosbag_messages::write_bag_messages((dir_ / "good-tf.bag").string(), m, /*as_tf=*/true);
    ASSERT_EQ(read_ros_bag(dir_ / "good.bag").scans.size(), 3u);
    ASSERT_EQ(read_ros_bag(dir_ / "good-tf.bag").scans.size(), 3u);
    good_ = testing::read_bytes(dir_ / "good.bag");
    good_tf_ = testing::read_bytes(dir_ / "good-tf.bag");
  }
  // The bytes of the bag with the 4 bytes after the first occurrence of `after` (plus `skip`) set to value.
  static std::string patched(const std::string& bag, std::string_view after, std::size_t skip, std::uint32_t value) {
    const std::size_t at = bag.find(after);
    std::string out = bag;
    if (at == std::string::npos) {
      ADD_FAILURE() << "no " << after << " in the bag";
      return out;
    }
    std::memcpy(out.data() + at + after.size() + skip, &value, 4);
    return out;
  }
  // The error reading these bytes gives ("no error" when there is none).
  std::string error(const std::string& bytes) {
    testing::write_bytes(dir_ / "bad.bag", bytes);
    try {
      read_ros_bag(dir_ / "bad.bag");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  }
  // The warnings of reading these bytes, which must give the three scans.
  std::string warnings(const std::string& bytes) {
    testing::write_bytes(dir_ / "bad.bag", bytes);
    const RosBagLog log = read_ros_bag(dir_ / "bad.bag");
    EXPECT_EQ(log.scans.size(), 3u);
    std::string all;
    for (const std::string& w : log.warnings) all += w + "\n";
    return all;
  }

  static constexpr std::uint32_t kMany = 0xffffffff;
  testing::TempDir dir_;
  std::string good_, good_tf_;
};

TEST_F(LyingBag, ArraysLongerThanTheMessageAreRefused) {
  using namespace std::string_view_literals;
  // A LaserScan whose ranges claim 2^29 floats (ROS's deserializer allocated 2 GB before checking).
  const std::string_view ranges = "\x03\x00\x00\x00\x00\x00\xc0\x3f"sv;  // 3 ranges, the first 1.5f
  std::string scan = good_;
  ASSERT_NE(scan.find(ranges), std::string::npos);
  const std::uint32_t floats = 0x20000000;
  std::memcpy(scan.data() + scan.find(ranges), &floats, 4);
  EXPECT_THAT(error(scan), HasSubstr("holds an array longer than the message"));
  // A TFMessage whose transform count is 2^32 - 1 (count, seq, stamp, then frame_id).
  const std::string_view frames = "\x04\x00\x00\x00odom\x09\x00\x00\x00" "base_link"sv;
  std::string tf = good_tf_;
  ASSERT_NE(tf.find(frames), std::string::npos);
  std::memcpy(tf.data() + tf.find(frames) - 16, &kMany, 4);
  EXPECT_THAT(error(tf), HasSubstr("holds an array longer than the message"));
}

TEST_F(LyingBag, AnIndexPastTheFileIsACutAndAChunkLyingAboutItsSizeDamage) {
  // The first record of the index section with a header of 2^32 - 1 bytes (librosbag allocated 4 GB).
  std::uint64_t index_pos = 0;
  std::memcpy(&index_pos, good_.data() + good_.find("index_pos=") + 10, 8);
  std::string index = good_;
  std::memcpy(index.data() + index_pos, &kMany, 4);
  // It runs past the end of the file, as when the file is cut there: the chunks before it are read, with a warning.
  EXPECT_THAT(warnings(index), HasSubstr("bad.bag: the file ends mid-record after byte " + std::to_string(index_pos)));
  // The index section past the end of the file (as in a file cut short between its chunks and its index); a chunk
  // claiming 4 GB uncompressed.
  EXPECT_THAT(warnings(patched(good_, "index_pos=", 0, 0x7fffffff)),
              HasSubstr("bad.bag: the file ends at byte " + std::to_string(good_.size()) +
                        ", before its index at byte 2147483647 (cut short); read the 3 scans of its 1 whole chunks"));
  EXPECT_THAT(error(patched(good_, "size=", 0, 0xffffffff)),
              HasSubstr("bad.bag: not a readable ROS 1 bag (the record at byte " +
                        std::to_string(good_.find("compression=") - 8) + " is damaged: a chunk of more than"));
  // A chunk that claims no bytes at all (size 0, data_len 0; the fuzzer's find: an empty copy from no buffer): the
  // bytes after its header are then read as the next record, which is damaged.
  std::string empty_chunk = patched(good_, "size=", 0, 0);
  const std::size_t at = good_.find("compression=") - 8;
  std::uint32_t header_len = 0;
  std::memcpy(&header_len, good_.data() + at, 4);
  const std::uint32_t none = 0;
  std::memcpy(empty_chunk.data() + at + 4 + header_len, &none, 4);
  EXPECT_THAT(error(empty_chunk), HasSubstr("bad.bag: not a readable ROS 1 bag"));
}

TEST_F(LyingBag, AnIndexEntryPastItsChunkIsRefusedOrWithSkipDamagedReadPast) {
  // The first index data record's first entry: its offset.
  std::string offset = good_;
  const std::size_t entry = first_index_entry(good_);
  ASSERT_NE(entry, 0u);
  std::memcpy(offset.data() + entry + 8, &kMany, 4);  // entry 0: time (8 bytes), offset (4 bytes)
  EXPECT_THAT(error(offset), HasSubstr("message data record at 4294967295: past the end"));
  // With skip_damaged a damaged index is read past: the chunks are walked without it.
  testing::write_bytes(dir_ / "bad.bag", offset);
  LogReadOptions skip;
  skip.skip_damaged = true;
  const RosBagLog skipped = read_ros_bag(dir_ / "bad.bag", skip);
  EXPECT_EQ(skipped.scans.size(), 3u);
  ASSERT_EQ(skipped.warnings.size(), 1u);
  EXPECT_THAT(skipped.warnings[0], HasSubstr("bad.bag: the bag's index is damaged (not a readable ROS 1 bag (message "
                                             "data record at 4294967295: past the end)); read the 3 scans"));
}

TEST_F(LyingBag, ABagNeverClosedIsReadWithoutItsIndexAndAnotherVersionRefused) {
  // A recording never closed (index_pos 0, as rosbag record leaves it until the end): read without its index.
  EXPECT_THAT(warnings(patched(good_, "index_pos=", 0, 0)),
              HasSubstr("bad.bag: the bag has no index (the recording was not closed); read the 3 scans of its 1 whole "
                        "chunks without it"));
  // Another bag format version.
  EXPECT_THAT(error("#ROSBAG V1.2\n" + good_.substr(13)), HasSubstr("only ROS bag format 2.0 is read"));
}

// librosbag builds a ros::Time from every time it reads, which throws a bare std::runtime_error ("Time is out of dual
// 32-bit range") when sec + nsec / 1e9 passes 2^32 - 1 (fuzz_ros_bag, ../shared/fuzz-findings): such a time is
// damage, named with where it is; skip_damaged reads the chunks without the index.
TEST(RosBag, ATimeOutOfRosRangeIsDamageNamedWhereItIs) {
  testing::TempDir dir;
  const rosbag_messages::BagMessages m = three_scans();
  rosbag_messages::write_bag_messages((dir / "good.bag").string(), m, /*as_tf=*/false);
  const std::string good = testing::read_bytes(dir / "good.bag");
  const std::uint32_t bad_time[2] = {0xfffffffeu, 4077344295u};  // the finding's: sec 2^32 - 2, nsec > 1e9
  const auto read = [&](const std::string& bytes, bool skip_damaged) {
    testing::write_bytes(dir / "bad.bag", bytes);
    LogReadOptions options;
    options.skip_damaged = skip_damaged;
    return read_ros_bag(dir / "bad.bag", options);
  };
  // In an index entry (where the finding had it), in a chunk info record and in a message record's header.
  std::string in_index = good, in_chunk_info = good, in_message = good;
  const std::size_t entry = first_index_entry(good);
  ASSERT_NE(entry, 0u);
  std::memcpy(in_index.data() + entry, bad_time, 8);
  ASSERT_NE(good.find("start_time="), std::string::npos);
  std::memcpy(in_chunk_info.data() + good.find("start_time=") + 11, bad_time, 8);
  ASSERT_NE(good.find("time="), std::string::npos);  // the first message record's (chunks are not compressed)
  std::memcpy(in_message.data() + good.find("time=") + 5, bad_time, 8);
  for (const auto& [bytes, where] : {std::pair{in_index, "index data record at "},
                                     std::pair{in_chunk_info, "chunk info record at "},
                                     std::pair{in_message, "message data record at "}}) {
    SCOPED_TRACE(where);
    try {
      read(bytes, false);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("bad.bag: not a readable ROS 1 bag (" + std::string(where)));
      EXPECT_THAT(e.what(), HasSubstr("a time out of ROS's range (sec 4294967294, nsec 4077344295)"));
    }
    const RosBagLog skipped = read(bytes, true);
    EXPECT_EQ(skipped.scans.size(), 3u);
    ASSERT_FALSE(skipped.warnings.empty());
    EXPECT_THAT(skipped.warnings[0], HasSubstr("bad.bag: the bag's index is damaged"));
  }
}

// Every input a fuzz target of ROS 1 bags ever found (fuzz/findings/fuzz_ros_bag, also the fuzzer's corpus: see
// fuzz/README.md) is read as the fuzzer reads it: scans, or an InputError naming the file; nothing else escapes.
TEST(RosBag, EveryPastFuzzFindingIsReadOrRefusedByName) {
  const std::filesystem::path findings = std::filesystem::path(PARTSLAM_SOURCE_DIR) / "fuzz/findings/fuzz_ros_bag";
  ASSERT_TRUE(std::filesystem::is_directory(findings)) << findings;
  std::size_t files = 0;
  for (const auto& f : std::filesystem::directory_iterator(findings)) {
    SCOPED_TRACE(f.path().string());
    ++files;
    for (const bool skip_damaged : {false, true}) {
      LogReadOptions options;
      options.skip_damaged = skip_damaged;
      try {
        const ScanSource source = load_scan_source(f.path().string(), options);
        EXPECT_FALSE(source.scans.empty());
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(f.path().string()));
      }
    }
  }
  EXPECT_GE(files, 1u);
}

// ---- bags cut short, corrupt chunks ----

// A top-level record of a bag file.
struct TopRecord {
  std::size_t pos = 0, end = 0;
  std::string header;  ///< the header's fields, each "length name=value"
};

std::vector<TopRecord> top_records(const std::string& bag) {
  std::vector<TopRecord> out;
  for (std::size_t pos = 13; pos + 8 <= bag.size();) {
    std::uint32_t header_len = 0, data_len = 0;
    std::memcpy(&header_len, bag.data() + pos, 4);
    std::memcpy(&data_len, bag.data() + pos + 4 + header_len, 4);
    const std::size_t end = pos + 8 + header_len + data_len;
    out.push_back({pos, end, bag.substr(pos + 4, header_len)});
    pos = end;
  }
  return out;
}

// The value of a header field, empty when there is none.
std::string header_field(const std::string& header, const std::string& name) {
  for (std::size_t at = 0; at + 4 <= header.size();) {
    std::uint32_t n = 0;
    std::memcpy(&n, header.data() + at, 4);
    const std::string field = header.substr(at + 4, n);
    if (field.rfind(name + "=", 0) == 0) return field.substr(name.size() + 1);
    at += 4 + n;
  }
  return {};
}

std::uint32_t u32_of(const std::string& bytes) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data(), std::min<std::size_t>(4, bytes.size()));
  return v;
}

// The chunks of a bag, from its index: where each ends and how many messages of `topic` it holds.
std::vector<std::pair<std::size_t, std::size_t>> chunks_of(const std::string& bag, const std::string& topic,
                                                           std::vector<std::size_t>* starts = nullptr) {
  const std::vector<TopRecord> records = top_records(bag);
  std::vector<std::uint32_t> connections;  // of the topic
  for (const TopRecord& r : records)
    if (header_field(r.header, "op") == "\x07" && header_field(r.header, "topic") == topic)
      connections.push_back(u32_of(header_field(r.header, "conn")));
  std::vector<std::pair<std::size_t, std::size_t>> chunks;
  for (const TopRecord& r : records) {
    const std::string op = header_field(r.header, "op");
    if (op == "\x05") {
      chunks.emplace_back(r.end, 0);
      if (starts != nullptr) starts->push_back(r.pos);
    } else if (op == "\x04" && !chunks.empty()) {
      const std::uint32_t conn = u32_of(header_field(r.header, "conn"));
      if (std::find(connections.begin(), connections.end(), conn) != connections.end())
        chunks.back().second += u32_of(header_field(r.header, "count"));
    }
  }
  return chunks;
}

void expect_same_scans(const Scans& part, const Scans& whole) {
  ASSERT_LE(part.size(), whole.size());
  for (std::size_t i = 0; i < part.size(); ++i) {
    ASSERT_EQ(part[i].timestamp, whole[i].timestamp) << i;
    ASSERT_EQ(part[i].points_laser, whole[i].points_laser) << i;
  }
}

// The aces bag cut at 20 random places: each cut reads the scans of the chunks wholly before the cut (as `rosbag
// reindex` recovers them), the first scans of the whole bag, with a warning.
TEST(RosBag, BagsCutShortReadTheScansOfTheirWholeChunks) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  EXPECT_TRUE(whole.warnings.empty());
  const std::string bytes = testing::read_bytes(source);
  const auto chunks = chunks_of(bytes, "/scan");
  ASSERT_GT(chunks.size(), 5u);
  std::size_t total = 0;
  for (const auto& c : chunks) total += c.second;
  ASSERT_EQ(total, whole.scans.size());
  testing::TempDir dir;
  std::mt19937_64 rng(24);
  for (int k = 0; k < 20; ++k) {
    const std::size_t cut = 4200 + rng() % (bytes.size() - 4200);
    SCOPED_TRACE("cut at " + std::to_string(cut));
    std::size_t before = 0;
    for (const auto& c : chunks) before += c.second * (c.first <= cut);
    testing::write_bytes(dir / "cut.bag", std::string_view(bytes).substr(0, cut));
    if (before == 0) {
      EXPECT_THAT([&] { load_scan_source((dir / "cut.bag").string()); },
                  ::testing::ThrowsMessage<InputError>(HasSubstr("no sensor_msgs/LaserScan messages; " +
                                                                 (dir / "cut.bag").string() + ": the file ends")));
      continue;
    }
    const RosBagLog part = read_ros_bag(dir / "cut.bag");
    EXPECT_EQ(part.scans.size(), before);
    expect_same_scans(part.scans, whole.scans);
    ASSERT_EQ(part.warnings.size(), 1u);
    EXPECT_THAT(part.warnings[0], HasSubstr("cut.bag: the file ends mid-record after byte "));
    EXPECT_THAT(part.warnings[0], HasSubstr("; read the " + std::to_string(before) + " scans of its "));
  }
  // Cut just after a chunk: a file of whole records without its index.
  testing::write_bytes(dir / "cut.bag", std::string_view(bytes).substr(0, chunks[3].first));
  const RosBagLog part = read_ros_bag(dir / "cut.bag");
  EXPECT_EQ(part.scans.size(), chunks[0].second + chunks[1].second + chunks[2].second + chunks[3].second);
  ASSERT_EQ(part.warnings.size(), 1u);
  EXPECT_THAT(part.warnings[0], HasSubstr("cut.bag: the file ends at byte " + std::to_string(chunks[3].first) +
                                          ", before its index at byte "));
}

TEST(RosBag, ACorruptChunkInTheMiddleIsAnErrorOrWithSkipDamagedSkippedAndCounted) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  std::string bytes = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(bytes, "/scan", &starts);
  ASSERT_GT(chunks.size(), 5u);
  for (std::size_t i = 0; i < 64; ++i) bytes[starts[2] + 2000 + i] = static_cast<char>(i * 37);  // its bz2 data
  testing::TempDir dir;
  testing::write_bytes(dir / "corrupt.bag", bytes);
  const std::string place = "the record at byte " + std::to_string(starts[2]) + " is damaged: ";
  EXPECT_THAT([&] { read_ros_bag(dir / "corrupt.bag"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("corrupt.bag: not a readable ROS 1 bag (" + place +
                                                             "a bz2 chunk that does not decompress to its size)")));
  LogReadOptions skip;
  skip.skip_damaged = true;
  const RosBagLog log = read_ros_bag(dir / "corrupt.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks[2].second);
  expect_same_scans(Scans(log.scans.begin(), log.scans.begin() + static_cast<long>(chunks[0].second + chunks[1].second)),
                    whole.scans);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("corrupt.bag: skipped 1 damaged record(s) (skip_damaged); the first: " + place));
}


// The scans of `whole` without those of chunk `skipped` (chunks: from chunks_of), which must be `part`.
void expect_all_but_chunk(const Scans& part, const Scans& whole,
                          const std::vector<std::pair<std::size_t, std::size_t>>& chunks, std::size_t skipped) {
  std::size_t first = 0;
  for (std::size_t c = 0; c < skipped; ++c) first += chunks[c].second;
  Scans expected(whole.begin(), whole.begin() + static_cast<long>(first));
  expected.insert(expected.end(), whole.begin() + static_cast<long>(first + chunks[skipped].second), whole.end());
  ASSERT_EQ(part.size(), expected.size());
  expect_same_scans(part, expected);
}

// A complete bag (its index, at the header's index_pos, within the file and intact) whose 7th chunk record has a
// length running past the end of the file is damaged, not cut short there (not just the scans of its first 6
// chunks, exit 0): an error naming the byte; with skip_damaged every other chunk is read, found from the index
// (the chunks after the damaged one too).
TEST(RosBag, ADamagedChunkLengthInACompleteBagIsDamageNotACut) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "fr079.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  const std::string good = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(good, "/scan", &starts);
  ASSERT_GT(chunks.size(), 7u);
  const std::size_t at = starts[6];
  std::uint32_t header_len = 0, data_len = 0;
  std::memcpy(&header_len, good.data() + at, 4);
  std::memcpy(&data_len, good.data() + at + 4 + header_len, 4);
  testing::TempDir dir;
  LogReadOptions skip;
  skip.skip_damaged = true;
  const std::string place = "the record at byte " + std::to_string(at) + " is damaged: ";
  struct Patch {
    const char* what;
    std::size_t offset;  ///< from the record's start
    std::uint32_t value;
    std::string problem;
  };
  const std::vector<Patch> patches{
      {"data_len past the end", 4 + header_len, 0xfffffff0u, "its length runs past the end of the file at byte "},
      {"header_len past the end", 0, static_cast<std::uint32_t>(good.size()), "its length runs past the end"},
      {"data_len shortened", 4 + header_len, data_len - 1000, "a bz2 chunk that does not decompress to its size"},
      {"data_len lengthened over the next chunk", 4 + header_len,
       static_cast<std::uint32_t>(starts[7] + 100 - (at + 8 + header_len)),
       "its length runs over the chunk at byte " + std::to_string(starts[7])}};
  for (const Patch& p : patches) {
    SCOPED_TRACE(p.what);
    std::string bytes = good;
    std::memcpy(bytes.data() + at + p.offset, &p.value, 4);
    testing::write_bytes(dir / "damaged.bag", bytes);
    EXPECT_THAT([&] { read_ros_bag(dir / "damaged.bag"); },
                ::testing::ThrowsMessage<InputError>(::testing::AllOf(
                    HasSubstr("damaged.bag: not a readable ROS 1 bag (" + place + p.problem), HasSubstr("skip_damaged"))));
    const RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
    expect_all_but_chunk(log.scans, whole.scans, chunks, 6);
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_THAT(log.warnings[0], HasSubstr("damaged.bag: skipped 1 damaged record(s) (skip_damaged); the first: " +
                                           place + p.problem));
    EXPECT_THAT(log.warnings[0], HasSubstr("; read the " + std::to_string(log.scans.size()) + " scans of its " +
                                           std::to_string(chunks.size() - 1) + " whole chunks (of the " +
                                           std::to_string(chunks.size()) + " its index lists)"));
  }
  // Two damaged chunks, one of them the last: both skipped and counted, the others read.
  std::string bytes = good;
  const std::uint32_t past = 0xfffffff0u;
  std::memcpy(bytes.data() + starts[2], &past, 4);
  std::memcpy(bytes.data() + starts.back(), &past, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  const RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks[2].second - chunks.back().second);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("skipped 2 damaged record(s) (skip_damaged); the first: the record at byte " +
                                         std::to_string(starts[2]) + " is damaged"));
}

// Without a readable index (here a recording never closed: index_pos 0), a chunk whose header cannot be read
// (so neither where it ends) does not end the walk with skip_damaged: the walker finds the next chunk record by its
// header and reads on; after the last chunk there is none to find, which a warning says.
TEST(RosBag, WithoutAnIndexSkipDamagedFindsTheNextChunkAfterOneWithBadLengths) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  std::string good = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(good, "/scan", &starts);
  ASSERT_GT(chunks.size(), 5u);
  const std::size_t index_pos_at = good.find("index_pos=") + 10;
  std::memset(good.data() + index_pos_at, 0, 8);  // never closed
  testing::TempDir dir;
  LogReadOptions skip;
  skip.skip_damaged = true;
  std::string bytes = good;
  // The length of its header's first field too long: the header cannot be read, nor so where the chunk ends.
  const std::uint32_t field_len = 0x7fffffff;
  std::memcpy(bytes.data() + starts[2] + 4, &field_len, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  const std::string place = "the record at byte " + std::to_string(starts[2]) + " is damaged: ";
  EXPECT_THAT([&] { read_ros_bag(dir / "damaged.bag"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("damaged.bag: not a readable ROS 1 bag (" + place)));
  RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
  expect_all_but_chunk(log.scans, whole.scans, chunks, 2);
  ASSERT_EQ(log.warnings.size(), 2u);
  EXPECT_THAT(log.warnings[0], HasSubstr("damaged.bag: the bag has no index (the recording was not closed)"));
  EXPECT_THAT(log.warnings[1], HasSubstr("damaged.bag: skipped 1 damaged record(s) (skip_damaged); the first: " + place));
  // The last chunk damaged so: nothing after it is found (its index data records and the index are read past).
  bytes = good;
  std::memcpy(bytes.data() + starts.back() + 4, &field_len, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  log = read_ros_bag(dir / "damaged.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks.back().second);
  ASSERT_EQ(log.warnings.size(), 3u);
  EXPECT_THAT(log.warnings[2], HasSubstr("damaged.bag: no chunk record was found after the damaged record at byte " +
                                         std::to_string(starts.back()) + ": the rest of the file"));
}

}  // namespace
}  // namespace partslam::io
