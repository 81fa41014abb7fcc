#include "io/logs/ros2_bag.h"

#include <yaml-cpp/yaml.h>
#include <zstd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <map>
#include <optional>
#include <variant>
#include <vector>

#include "core/error.h"
#include "io/logs/bag_selection.h"
#include "io/logs/cdr.h"
#include "io/logs/mcap_file.h"
#include "io/files/sqlite.h"
#include "io/files/sqlite_salvage.h"

namespace partslam::io {
namespace {

namespace rm = rosbag_messages;

constexpr const char* kLaserScan = "sensor_msgs/msg/LaserScan";
constexpr const char* kOdometry = "nav_msgs/msg/Odometry";
constexpr const char* kTf = "tf2_msgs/msg/TFMessage";

struct OdometryEvent {
  std::string child_frame;
  rm::OdometryMessage message;
};

// One decoded message, kept until all are read and put in time order.
struct Event {
  std::uint64_t time_ns = 0;
  std::string topic;
  std::variant<rm::LaserScanMessage, OdometryEvent, std::vector<cdr::StampedTransform>> message;
};

// What one storage file gave, and how its reading ended.
struct FileRead {
  std::vector<Event> events;
  std::vector<std::pair<std::string, std::string>> topics;  // topic, type
  std::size_t damaged = 0;
  std::string first_damage;
  std::string cut;  // non-empty: where the file was cut short
};

class Decoder {
 public:
  Decoder(const LogReadOptions& options, bool zstd_messages, bool detect_zstd = false)
      : options_(options), zstd_messages_(zstd_messages), detect_zstd_(detect_zstd) {}
  bool skip_damaged() const { return options_.skip_damaged; }

  // Decodes one message; "where" names it for errors. Damage is counted when skip_damaged, else thrown.
  void add(FileRead& out, const std::string& topic, const std::string& type, const std::string& encoding,
           std::uint64_t time_ns, std::span<const std::uint8_t> data, const std::string& where) {
    const auto seen = [&](const auto& t) { return t.first == topic; };
    if (std::none_of(out.topics.begin(), out.topics.end(), seen)) out.topics.emplace_back(topic, type);
    if (type != kLaserScan && type != kOdometry && type != kTf) return;
    if (!options_.scan_topic.empty() && type == kLaserScan && topic != options_.scan_topic) return;
    try {
      if (encoding != "cdr") throw rm::BagError("message encoding '" + encoding + "' (only cdr is read)");
      std::vector<std::uint8_t> plain;
      if (zstd_messages_ || (detect_zstd_ && is_zstd_frame(data))) {
        plain = unzstd(data);
        data = plain;
      }
      Event e{time_ns, topic, {}};
      if (type == kLaserScan) {
        e.message = cdr::laser_scan(data);
        ranges_ += std::get<rm::LaserScanMessage>(e.message).ranges.size();
        if (ranges_ > options_.max_points)
          throw InputError(where + ": more than " + std::to_string(options_.max_points) +
                           " ranges (LogReadOptions.max_points)");
      } else if (type == kOdometry) {
        OdometryEvent o;
        o.message = cdr::odometry(data, o.child_frame);
        e.message = std::move(o);
      } else {
        e.message = cdr::tf_message(data);
      }
      out.events.push_back(std::move(e));
    } catch (const rm::BagError& err) {
      const std::string what = where + " (" + topic + ", " + type + "): " + err.what();
      if (!options_.skip_damaged) throw InputError(what + " (skip_damaged skips damaged messages)");
      if (out.damaged++ == 0) out.first_damage = what;
    }
  }

 private:
  static std::vector<std::uint8_t> unzstd(std::span<const std::uint8_t> data) {
    const unsigned long long size = ZSTD_getFrameContentSize(data.data(), data.size());
    if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN || size > (256ull << 20))
      throw rm::BagError("not a zstd frame of known size (compression_mode MESSAGE)");
    std::vector<std::uint8_t> out(static_cast<std::size_t>(size));
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
    if (ZSTD_isError(n) || n != out.size()) throw rm::BagError("its zstd data does not decompress");
    return out;
  }

  const LogReadOptions& options_;
  bool zstd_messages_;
  bool detect_zstd_;
  // A zstd frame starts with its magic number; a CDR message with its encapsulation header (0x00 0x00|0x01 ...).
  static bool is_zstd_frame(std::span<const std::uint8_t> data) {
    return data.size() >= 4 && data[0] == 0x28 && data[1] == 0xb5 && data[2] == 0x2f && data[3] == 0xfd;
  }
  std::size_t ranges_ = 0;
};

FileRead read_mcap(const std::filesystem::path& path, Decoder& decoder, const LogReadOptions& options) {
  FileRead out;
  const std::string name = path.string();
  std::uint64_t index = 0;
  const mcap::ReadReport report = mcap::read_messages(
      path,
      [&](const mcap::Channel& c, std::uint64_t time_ns, std::span<const std::uint8_t> data) {
        decoder.add(out, c.topic, c.schema_name, c.message_encoding, time_ns, data,
                    name + ": message " + std::to_string(index++));
      },
      options.skip_damaged);
  out.damaged += report.damaged_chunks;
  if (out.first_damage.empty()) out.first_damage = report.first_damage;
  if (report.truncated) {
    out.cut = "the file (" + std::to_string(report.file_bytes) + " bytes) ends inside the record at byte " +
              std::to_string(report.read_bytes) + "; read every record before it";
    if (report.cut_chunk_records > 0)
      out.cut += " and the first " + std::to_string(report.cut_chunk_records) + " records of that chunk";
  }
  return out;
}

// A row of a .db3's topics table.
struct Topic {
  std::string name, type, format;
};

// The rows of a .db3 cut short, from its pages (io/files/sqlite_salvage.h): topics rows (id, name, type, format, qos,
// ...) and messages rows (id, topic_id, timestamp, data), each whole before the cut.
void salvage_db3(const std::filesystem::path& path, Decoder& decoder, FileRead& out) {
  using Text = std::span<const std::uint8_t>;
  struct Row {
    std::int64_t topic;
    std::uint64_t time;
    std::vector<std::uint8_t> data;
  };
  std::map<std::int64_t, Topic> topics;
  std::map<std::int64_t, Row> rows;
  const auto text = [](const sqlite::Value& v) {
    const Text t = std::get<Text>(v);
    return std::string(t.begin(), t.end());
  };
  sqlite::salvage_rows(path, [&](std::int64_t rowid, const std::vector<sqlite::Value>& v) {
    if (v.empty() || !std::holds_alternative<std::monostate>(v[0])) return;  // rosbag2's ids alias the rowid
    if (v.size() >= 5 && std::holds_alternative<Text>(v[1]) && std::holds_alternative<Text>(v[2]) &&
        std::holds_alternative<Text>(v[3]))
      topics[rowid] = {text(v[1]), text(v[2]), text(v[3])};
    else if (v.size() == 4 && std::holds_alternative<std::int64_t>(v[1]) &&
             std::holds_alternative<std::int64_t>(v[2]) && std::holds_alternative<Text>(v[3])) {
      const Text d = std::get<Text>(v[3]);
      rows[rowid] = {std::get<std::int64_t>(v[1]), static_cast<std::uint64_t>(std::get<std::int64_t>(v[2])),
                     {d.begin(), d.end()}};
    }
  });
  const std::string name = path.string();
  std::int64_t last = 0;
  for (const auto& [id, row] : rows) {
    const auto topic = topics.find(row.topic);
    if (topic == topics.end()) continue;  // its topics row lay past the cut
    decoder.add(out, topic->second.name, topic->second.type, topic->second.format, row.time, row.data,
                name + ": messages row " + std::to_string(id));
    last = id;
  }
  out.cut = "read the " + std::to_string(rows.size()) + " whole messages rows of the pages before the cut, up to row " +
            std::to_string(last);
}

FileRead read_db3(const std::filesystem::path& path, Decoder& decoder) {
  FileRead out;
  const std::string name = path.string();
  std::error_code ec;
  const std::uint64_t bytes = std::filesystem::file_size(path, ec);
  if (ec) throw InputError(name + ": " + ec.message());
  const std::optional<sqlite::FileHeader> header = sqlite::read_file_header(path);
  if (!header)
    throw InputError(name + ": not a rosbag2 SQLite file (it does not start with the SQLite header)");
  if (bytes < header->page_size * header->page_count) {  // cut short: SQLite cannot open it
    salvage_db3(path, decoder, out);
    return out;
  }
  const sqlite::Connection db = sqlite::Connection::open(path, sqlite::Connection::Access::kReadOnly);
  std::map<std::int64_t, Topic> topics;
  try {
    sqlite::Statement t(db, "SELECT id, name, type, serialization_format FROM topics");
    while (t.step()) topics[t.int64(0)] = {t.text(1), t.text(2), t.text(3)};
  } catch (const InputError& e) {
    throw InputError(name + ": not a rosbag2 SQLite file (" + e.what() + ")");
  }
  std::int64_t row = 0;
  sqlite::Statement m(db, "SELECT id, topic_id, timestamp, data FROM messages ORDER BY id");
  for (;;) {
    try {
      if (!m.step()) break;
    } catch (const InputError& e) {
      // A damaged page: SQLite stops there. With skip_damaged, every row the pages still hold whole is read instead.
      const std::string what = std::string(e.what()) + " (after messages row " + std::to_string(row) + ")";
      if (!decoder.skip_damaged()) throw InputError(what + "; skip_damaged reads the rows its pages still hold");
      FileRead salvaged;
      salvage_db3(path, decoder, salvaged);
      salvaged.cut.clear();
      salvaged.damaged += 1;
      salvaged.first_damage = what;
      return salvaged;
    }
    row = m.int64(0);
    const auto topic = topics.find(m.int64(1));
    if (topic == topics.end())
      throw InputError(name + ": messages row " + std::to_string(row) + " names topic " + std::to_string(m.int64(1)) +
                       ", which the topics table does not hold");
    decoder.add(out, topic->second.name, topic->second.type, topic->second.format,
                static_cast<std::uint64_t>(m.int64(2)), m.blob(3), name + ": messages row " + std::to_string(row));
  }
  return out;
}

struct Storage {
  std::vector<std::filesystem::path> files;
  bool zstd_messages = false;
  bool detect_zstd = false;  ///< no metadata.yaml: a message that is a zstd frame is decompressed
  std::map<std::string, std::uint64_t> counts;  ///< messages per topic, as metadata.yaml states them
  std::string warning;
};

// The storage files of a rosbag2 folder (.db3, .mcap), in the order rosbag2 splits them: <name>_<k>.<ext> by k.
std::vector<std::filesystem::path> storage_files(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    const std::filesystem::path& p = entry.path();
    if ((p.extension() == ".db3" || p.extension() == ".mcap") && entry.is_regular_file(ec)) files.push_back(p);
  }
  const auto split_index = [](const std::filesystem::path& p) {
    const std::string stem = p.stem().string();
    const std::size_t digits = stem.find_last_not_of("0123456789") + 1;
    const bool numbered = digits < stem.size() && digits > 0 && stem[digits - 1] == '_' && stem.size() - digits < 10;
    return std::pair(numbered ? stem.substr(0, digits) : stem, numbered ? std::stoul(stem.substr(digits)) : 0ul);
  };
  std::sort(files.begin(), files.end(), [&](const auto& a, const auto& b) {
    return std::pair(split_index(a), a.filename()) < std::pair(split_index(b), b.filename());
  });
  return files;
}

// Messages per topic as metadata.yaml's topics_with_message_count states them (none when it does not).
std::map<std::string, std::uint64_t> stated_counts(const YAML::Node& info) {
  std::map<std::string, std::uint64_t> counts;
  const YAML::Node topics = info["topics_with_message_count"];
  if (!topics || !topics.IsSequence()) return counts;
  for (const YAML::Node& t : topics) {
    const YAML::Node name = t["topic_metadata"] ? t["topic_metadata"]["name"] : YAML::Node();
    if (name && t["message_count"]) counts[name.as<std::string>()] = t["message_count"].as<std::uint64_t>();
  }
  return counts;
}

Storage storage_of(std::filesystem::path path) {
  if (path.filename() == "metadata.yaml") path = path.parent_path().empty() ? "." : path.parent_path();
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) {
    if (!std::filesystem::exists(path, ec)) throw InputError(name + ": no such file");
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(name + ": not a regular file");
    Storage s;
    s.files = {path};
    return s;
  }
  const std::filesystem::path meta = path / "metadata.yaml";
  Storage s;
  if (!std::filesystem::exists(meta, ec)) {  // as after a power loss: the files as `ros2 bag reindex` finds them
    s.files = storage_files(path);
    if (s.files.empty()) throw InputError(name + ": a folder without metadata.yaml or any .db3 or .mcap file");
    s.detect_zstd = true;
    s.warning = name + ": no metadata.yaml (a recording not closed, or the file lost); read the " +
                std::to_string(s.files.size()) + " storage files in it in split order, as `ros2 bag reindex` would";
    return s;
  }
  try {
    const YAML::Node info = YAML::LoadFile(meta.string())["rosbag2_bagfile_information"];
    if (!info) throw InputError(meta.string() + ": no rosbag2_bagfile_information (not a rosbag2 metadata file)");
    // rosbag2 reads these case-insensitively ("message", "MESSAGE").
    const auto upper = [](std::string v) {
      for (char& c : v) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      return v;
    };
    const std::string mode = upper(info["compression_mode"] ? info["compression_mode"].as<std::string>() : "");
    const std::string format = upper(info["compression_format"] ? info["compression_format"].as<std::string>() : "");
    if (mode == "MESSAGE" && format == "ZSTD") s.zstd_messages = true;
    else if (!mode.empty() && mode != "NONE")
      throw InputError(meta.string() + ": compression_mode " + mode + " with format " + format +
                       " is not read (only per-message zstd is; decompress the files first)");
    const YAML::Node files = info["relative_file_paths"];
    if (!files || !files.IsSequence() || files.size() == 0)
      throw InputError(meta.string() + ": relative_file_paths: missing or empty");
    for (const YAML::Node& f : files) s.files.push_back(path / f.as<std::string>());
    s.counts = stated_counts(info);
  } catch (const YAML::Exception& e) {
    throw InputError(meta.string() + ": " + e.what());
  }
  return s;
}

std::string seconds(std::uint64_t ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", 1e-9 * static_cast<double>(ns));
  return text;
}

}  // namespace

bool is_ros2_bag(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    return std::filesystem::exists(path / "metadata.yaml", ec) || !storage_files(path).empty();
  return path.extension() == ".mcap" || path.extension() == ".db3" || path.filename() == "metadata.yaml";
}

RosBagLog read_ros2_bag(const std::filesystem::path& path, const LogReadOptions& options) {
  validate(options);
  const std::string name = path.string();
  const Storage storage = storage_of(path);
  Decoder decoder(options, storage.zstd_messages, storage.detect_zstd);
  std::vector<Event> events;
  std::vector<std::string> warnings;
  if (!storage.warning.empty()) warnings.push_back(storage.warning);
  rm::BagSelection selection(options.max_points, options.scan_topic, options.odom_topic);
  for (std::size_t k = 0; k < storage.files.size(); ++k) {
    const std::filesystem::path& file = storage.files[k];
    const bool mcap = file.extension() == ".mcap" || mcap::has_mcap_magic(file);
    if (!mcap && file.extension() != ".db3" && std::filesystem::is_regular_file(file))
      throw InputError(file.string() + ": neither an MCAP (.mcap) nor a SQLite (.db3) rosbag2 file");
    FileRead read = mcap ? read_mcap(file, decoder, options) : read_db3(file, decoder);
    for (const auto& [topic, type] : read.topics) selection.note_topic(topic, type);
    std::size_t scans = 0;
    std::uint64_t last = 0;
    for (const Event& e : read.events) {
      if (std::holds_alternative<rm::LaserScanMessage>(e.message)) ++scans, last = std::max(last, e.time_ns);
    }
    if (read.damaged > 0)
      warnings.push_back(file.string() + ": skipped " + std::to_string(read.damaged) + " damaged " +
                         (mcap ? "chunks or messages" : "pages or messages") + " (the first: " + read.first_damage + ")");
    if (!read.cut.empty()) {
      warnings.push_back(file.string() + ": the recording is cut short: " + read.cut + " (" + std::to_string(scans) +
                         " scans, up to log time " + seconds(last) + " s)" +
                         (k + 1 < storage.files.size() ? "; the files after it are read too" : ""));
    }
    std::move(read.events.begin(), read.events.end(), std::back_inserter(events));
  }
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) { return a.time_ns < b.time_ns; });
  rm::BagMessages messages;
  try {
    for (Event& e : events) {
      if (auto* scan = std::get_if<rm::LaserScanMessage>(&e.message)) {
        if (selection.wants_scan(e.topic)) selection.add_scan(e.topic, std::move(*scan));
      } else if (auto* odom = std::get_if<OdometryEvent>(&e.message)) {
        selection.add_odometry(e.topic, odom->child_frame, odom->message);
      } else {
        for (const cdr::StampedTransform& t : std::get<std::vector<cdr::StampedTransform>>(e.message))
          selection.add_transform(e.topic, t.stamp, t.transform);
      }
    }
    messages = std::move(selection).finish();
  } catch (const rm::BagError& e) {
    throw InputError(name + ": " + e.what());
  }
  // The scans read against the count metadata.yaml states for their topic.
  if (const auto stated = storage.counts.find(messages.scan_topic); stated != storage.counts.end()) {
    const auto read = static_cast<std::uint64_t>(std::count_if(events.begin(), events.end(), [&](const Event& e) {
      return e.topic == messages.scan_topic && std::holds_alternative<rm::LaserScanMessage>(e.message);
    }));
    if (read != stated->second)
      warnings.push_back(name + ": its metadata.yaml says " + messages.scan_topic + " holds " +
                         std::to_string(stated->second) + " messages, its storage files hold " +
                         std::to_string(read) + " (files missing, cut short or edited)");
  }
  RosBagLog log = scans_from_bag_messages(messages, options, name);
  log.warnings.insert(log.warnings.end(), warnings.begin(), warnings.end());
  return log;
}

}  // namespace partslam::io
