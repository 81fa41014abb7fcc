#include "io/config_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/yaml_text.h"

namespace partslam::io {
namespace {

// ---- the fields of every config, one list per struct, walked by the reader and the writer alike ----

template <class V>
void visit(V& v, ScanMatcherConfig& c) {
  v.field("resolution", c.resolution);
  v.field("sigma", c.sigma);
  v.field("linear_window", c.linear_window);
  v.field("angular_window", c.angular_window);
  v.field("max_iterations", c.max_iterations);
  v.field("num_threads", c.num_threads);
}

template <class V>
void visit(V& v, FrontEndConfig& c) {
  v.section("matcher", c.matcher);
  v.field("fine_sigma", c.fine_sigma);
  v.field("max_range", c.max_range);
  v.field("point_resolution", c.point_resolution);
  v.field("local_map_scans", c.local_map_scans);
  v.field("key_translation", c.key_translation);
  v.field("key_rotation", c.key_rotation);
  v.field("min_score", c.min_score);
  v.field("degenerate_ratio", c.degenerate_ratio);
  v.field("jump_turn", c.jump_turn);
  v.field("second_prediction", c.second_prediction);
  v.field("second_margin", c.second_margin);
}

template <class V>
void visit(V& v, SubmapConfig& c) {
  v.field("window_length", c.window_length);
  v.field("spacing", c.spacing);
  v.field("resolution", c.resolution);
  v.field("crop_size", c.crop_size);
  v.field("max_range", c.max_range);
  v.field("min_points", c.min_points);
  v.field("align", c.align);
}

template <class V>
void visit(V& v, LoopClosureConfig& c) {
  v.field("method", c.method);
  v.field("min_travel_gap", c.min_travel_gap);
  v.field("other_place", c.other_place);
  v.field("min_score", c.min_score);
  v.field("context", c.context);
  v.field("drift_offset", c.drift_offset);
  v.field("drift_rate", c.drift_rate);
  v.field("drift_turn", c.drift_turn);
  v.field("drift_turn_rate", c.drift_turn_rate);
  v.field("graph_check", c.graph_check);
  v.field("verify_dmm", c.verify_dmm);
  v.field("num_threads", c.num_threads);
}

template <class V>
void visit(V& v, SubmapGraphWeights& c) {
  v.field("chain_translation", c.chain_translation);
  v.field("chain_rotation", c.chain_rotation);
  v.field("loop_translation", c.loop_translation);
  v.field("loop_rotation", c.loop_rotation);
}

template <class V>
void visit(V& v, PoseGraphConfig& c) {
  v.field("robust_scale", c.robust_scale);
  v.field("max_iterations", c.max_iterations);
}

template <class V>
void visit(V& v, BackEndConfig& c) {
  v.section("weights", c.weights);
  v.section("graph", c.graph);
  v.field("max_translation_residual", c.max_translation_residual);
  v.field("max_rotation_residual", c.max_rotation_residual);
  v.field("max_rounds", c.max_rounds);
  v.field("max_rejected_share", c.max_rejected_share);
  v.field("max_chain_translation", c.max_chain_translation);
  v.field("max_chain_rotation", c.max_chain_rotation);
}

template <class V>
void visit(V& v, MapCheckConfig& c) {
  v.field("resolution", c.resolution);
  v.field("max_range", c.max_range);
  v.field("key_spacing", c.key_spacing);
  v.field("min_gap", c.min_gap);
  v.field("end_margin", c.end_margin);
  v.field("min_hits", c.min_hits);
  v.field("own_cells", c.own_cells);
  v.field("place_size", c.place_size);
  v.field("min_place_beams", c.min_place_beams);
  v.field("max_crossing_share", c.max_crossing_share);
  v.field("max_place_share", c.max_place_share);
  v.field("min_revisiting_beams", c.min_revisiting_beams);
}

template <class V>
void visit(V& v, SlamConfig& c) {
  v.section("front_end", c.front_end);
  v.section("submaps", c.submaps);
  v.section("loops", c.loops);
  v.field("min_confidence", c.min_confidence);
  v.section("back_end", c.back_end);
  v.section("map_check", c.map_check);
}

template <class V>
void visit(V& v, LoopTruthConfig& c) {  // min_travel_gap: the loops' (LoopsConfig)
  v.field("radius", c.radius);
  v.field("max_translation_error", c.max_translation_error);
  v.field("max_rotation_error", c.max_rotation_error);
}

template <class V>
void visit(V& v, LoopsConfig& c) {
  v.section("loops", c.loops);
  v.field("min_confidence", c.min_confidence);
  v.section("truth", c.truth);
}

template <class V>
void visit(V& v, DmmConfig& c) {
  v.field("resolution", c.resolution);
  v.field("linear_window", c.linear_window);
  v.field("angular_window", c.angular_window);
  v.field("angular_step", c.angular_step);
  v.field("canonical", c.canonical);
  v.field("canonical_turns", c.canonical_turns);
  v.field("extra_window", c.extra_window);
  v.field("dilation", c.dilation);
  v.field("search_depth", c.search_depth);
}

template <class V>
void visit(V& v, VerifyConfig& c) {
  v.field("resolution", c.resolution);
  v.field("dilation", c.dilation);
  v.field("max_ray", c.max_ray);
  v.field("refine_window", c.refine_window);
  v.field("refine_angle", c.refine_angle);
  v.field("alternatives", c.alternatives);
  v.field("alternative_bar", c.alternative_bar);
  v.field("alternative_distance", c.alternative_distance);
  v.field("alternative_angle", c.alternative_angle);
  v.field("refined", c.refined);
}

template <class V>
void visit(V& v, LocalizerConfig& c) {
  v.section("dmm", c.dmm);
  v.section("verify", c.verify);
  v.field("elsewhere_distance", c.elsewhere_distance);
  v.field("elsewhere_angle", c.elsewhere_angle);
  v.field("candidate_distance", c.candidate_distance);
  v.field("candidates", c.candidates);
  v.field("free_weight", c.free_weight);
  v.field("neighbourhood", c.neighbourhood);
  v.field("wall_direction_share", c.wall_direction_share);
  v.field("wall_direction_length", c.wall_direction_length);
  v.field("verified", c.verified);
  v.field("restart_distance", c.restart_distance);
}

template <class V>
void visit(V& v, LocateConfig& c) {
  v.section("submaps", c.submaps);
  v.section("localizer", c.localizer);
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
}

void read_config_file(const std::filesystem::path& file, SlamConfig& config) { read_file(file, config); }
void read_config_file(const std::filesystem::path& file, LoopsConfig& config) { read_file(file, config); }
void read_config_file(const std::filesystem::path& file, LocateConfig& config) { read_file(file, config); }

std::string config_yaml(const SlamConfig& config) { return yaml_of(config, "slam"); }
std::string config_yaml(const LoopsConfig& config) { return yaml_of(config, "loops"); }
std::string config_yaml(const LocateConfig& config) { return yaml_of(config, "locate"); }

}  // namespace partslam::io
