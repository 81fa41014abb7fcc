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
  Decoder(const LogReadOptions& options, bool zstd_messages) : options_(options), zstd_messages_(zstd_messages) {}
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
      if (zstd_messages_) {
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
  if (report.truncated)
    out.cut = "byte " + std::to_string(report.read_bytes) + " of " + std::to_string(report.file_bytes);
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
  out.cut = "messages row " + std::to_string(last) + " (" + std::to_string(rows.size()) +
            " whole rows in the pages before the cut)";
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
};

Storage storage_of(std::filesystem::path path) {
  if (path.filename() == "metadata.yaml") path = path.parent_path().empty() ? "." : path.parent_path();
  const std::string name = path.string();
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec)) {
    if (!std::filesystem::exists(path, ec)) throw InputError(name + ": no such file");
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(name + ": not a regular file");
    return {{path}, false};
  }
  const std::filesystem::path meta = path / "metadata.yaml";
  Storage s;
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
  if (std::filesystem::is_directory(path, ec)) return std::filesystem::exists(path / "metadata.yaml", ec);
  return path.extension() == ".mcap" || path.extension() == ".db3" || path.filename() == "metadata.yaml";
}

RosBagLog read_ros2_bag(const std::filesystem::path& path, const LogReadOptions& options) {
  validate(options);
  const std::string name = path.string();
  const Storage storage = storage_of(path);
  Decoder decoder(options, storage.zstd_messages);
  std::vector<Event> events;
  std::vector<std::string> warnings;
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
      warnings.push_back(file.string() + ": the recording is cut short; read it up to its last whole message, " +
                         read.cut + ": " + std::to_string(scans) + " scans, up to log time " + seconds(last) + " s" +
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
  RosBagLog log = scans_from_bag_messages(messages, options, name);
  log.warnings.insert(log.warnings.end(), warnings.begin(), warnings.end());
  return log;
}

}  // namespace partslam::io
