#include "io/formats/config_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/files/yaml_text.h"

namespace partslam::io {
namespace {

// ---- the fields of every config (config_fields.h), walked on one object by the reader and the writer alike ----

// A table's member pointers applied to one object: v.field(key, value) and v.section(key, nested object).
template <class V, class T>
struct OnObject {
  V& v;
  T& object;
  template <class M>
  void field(const char* key, M T::*member, const char*) {
    v.field(key, object.*member);
  }
  template <class M, class P>
  void field(const char* key, M T::*member, P M::*part, const char*) {
    v.field(key, (object.*member).*part);
  }
  template <class S>
  void section(const char* key, S T::*member, const char*) {
    v.section(key, object.*member);
  }
};

template <class V, class T>
void visit(V& v, T& object) {
  OnObject<V, T> on{v, object};
  config_fields(on, std::type_identity<T>{});
}

// ---- reading ----

template <class T>
const char* kind() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  else if constexpr (std::is_same_v<T, int>) return "an integer";
  else if constexpr (std::is_same_v<T, double>) return "a number";
  else return "a string";
}

class Reader {
 public:
  Reader(YAML::Node map, std::string file, std::string path)
      : map_(std::move(map)), file_(std::move(file)), path_(std::move(path)) {}

  template <class T>
  void field(const char* key, T& value) {
    known_.push_back(key);
    const YAML::Node node = map_[key];
    if (!node) return;
    const std::string what = std::string("expected ") + kind<T>() + ", got ";
    if (!node.IsScalar()) fail(node, key, what + (node.IsMap() ? "a map" : node.IsSequence() ? "a list" : "nothing"));
    try {
      value = node.as<T>();
    } catch (const YAML::Exception&) {
      fail(node, key, what + "'" + node.Scalar() + "'");
    }
  }

  template <class S>
  void section(const char* key, S& s) {
    known_.push_back(key);
    const YAML::Node node = map_[key];
    if (!node) return;
    if (!node.IsMap()) fail(node, key, "expected a map of settings");
    Reader inner(node, file_, name(key));
    visit(inner, s);
    inner.refuse_unknown();
  }

  /// Every key of the map must be one of the fields visited.
  void refuse_unknown() const {
    for (const auto& entry : map_) {
      const std::string key = entry.first.Scalar();
      if (std::find(known_.begin(), known_.end(), key) != known_.end()) continue;
      std::string known;
      for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
      throw InputError(file_ + ": line " + std::to_string(entry.first.Mark().line + 1) + ": unknown key '" +
                       name(key) + "' (the keys " + (path_.empty() ? "at the top" : "of " + path_) + ": " + known +
                       ")");
    }
  }

 private:
  std::string name(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  [[noreturn]] void fail(const YAML::Node& node, const char* key, const std::string& what) const {
    throw InputError(file_ + ": line " + std::to_string(node.Mark().line + 1) + ": " + name(key) + ": " + what);
  }

  YAML::Node map_;
  std::string file_;
  std::string path_;
  std::vector<std::string> known_;
};

template <class Config>
void read_file(const std::filesystem::path& path, Config& config) {
  const std::string file = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(file + ": a folder, not a YAML settings file");
  if (holds_binary_data(path)) throw InputError(file + ": binary data, not a YAML settings file");
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw InputError(file + ": cannot open the settings file");
  } catch (const YAML::Exception& e) {
    throw InputError(file + ": line " + std::to_string(e.mark.line + 1) + ": not valid YAML (" + e.msg + ")");
  }
  if (root.IsNull()) return validate(config);  // an empty file: the defaults
  if (!root.IsMap()) throw InputError(file + ": expected a map of settings (key: value lines)");
  Reader reader(root, file, "");
  visit(reader, config);
  reader.refuse_unknown();
  try {
    validate(config);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

// ---- writing ----

class Writer {
 public:
  void field(const char* key, double v) { line(key) << number(v) << "\n"; }
  void field(const char* key, int v) { line(key) << v << "\n"; }
  void field(const char* key, bool v) { line(key) << (v ? "true" : "false") << "\n"; }
  void field(const char* key, const std::string& v) { line(key) << yaml_double_quoted(v) << "\n"; }
  template <class S>
  void section(const char* key, S& s) {
    out_ << indent() << key << ":\n";
    ++depth_;
    visit(*this, s);
    --depth_;
  }
  std::string text() const { return out_.str(); }

 private:
  std::string indent() const { return std::string(2 * static_cast<std::size_t>(depth_), ' '); }
  std::ostream& line(const char* key) { return out_ << indent() << key << ": "; }

  // The shortest text that reads back to the same double.
  static std::string number(double v) {
    if (std::isnan(v)) return ".nan";
    if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
    char text[40];
    const auto end = std::to_chars(text, text + sizeof text, v).ptr;
    std::string s(text, end);
    if (s.find_first_of(".e") == std::string::npos) s += ".0";  // stays a number of type double to the eye
    return s;
  }

  std::ostringstream out_;
  int depth_ = 0;
};

template <class Config>
std::string yaml_of(const Config& config, const char* command) {
  Config copy = config;
  Writer w;
  visit(w, copy);
  return std::string("# partslam ") + command + " --config: every setting (a key left out keeps its default)\n" +
         w.text();
}

}  // namespace

void validate(const LoopsConfig& c) {
  validate_nested("loops config", "loops", [&] { validate(c.loops); });
  if (!std::isfinite(c.min_confidence))
    throw InputError("loops config: min_confidence must be finite, got " + std::to_string(c.min_confidence));
  validate_nested("loops config", "truth", [&] { validate(c.truth); });
}

void validate(const LocateConfig& c) {
  validate_nested("locate config", "submaps", [&] { validate(c.submaps); });
  validate_nested("locate config", "localizer.dmm", [&] { validate(c.localizer.dmm); });
  validate_nested("locate config", "localizer", [&] { validate(c.localizer); });
  validate_nested("locate config", "tracker", [&] { validate(c.tracker); });
}

void read_config_file(const std::filesystem::path& file, SlamConfig& config) { read_file(file, config); }
void read_config_file(const std::filesystem::path& file, LoopsConfig& config) { read_file(file, config); }
void read_config_file(const std::filesystem::path& file, LocateConfig& config) { read_file(file, config); }

std::string config_yaml(const SlamConfig& config) { return yaml_of(config, "slam"); }
std::string config_yaml(const LoopsConfig& config) { return yaml_of(config, "loops"); }
std::string config_yaml(const LocateConfig& config) { return yaml_of(config, "locate"); }

}  // namespace partslam::io
