#include "io/logs/relations.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "core/error.h"
#include "io/files/line_reader.h"
#include "io/files/text_fields.h"

namespace partslam::io {
namespace {

constexpr std::string_view kRelation = "relation";
constexpr const char* kFields[] = {"t1", "t2", "x", "y", "z", "roll", "pitch", "yaw"};

}  // namespace

Relations read_relations(const std::filesystem::path& path) {
  LineReader reader(path);
  Relations relations;
  std::vector<std::string_view> tokens;
  std::string_view line;
  while (reader.next(line)) {
    split_fields(line, tokens);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    constexpr std::size_t kWant = std::size(kFields);
    double v[kWant] = {};
    for (std::size_t k = 0; k < std::min(kWant, tokens.size()); ++k) {
      v[k] = parse_number(reader, tokens[k], {kRelation, kFields[k]});
    }
    if (tokens.size() < kWant) {
      fail_field(reader, {kRelation, kFields[tokens.size()]},
                 "missing (line has " + std::to_string(tokens.size()) +
                     " fields, expected 8: t1 t2 x y z roll pitch yaw)");
    }
    if (tokens.size() > kWant) {
      fail_field(reader, {kRelation, ""},
                 std::to_string(tokens.size() - kWant) + " extra field(s) (expected 8)");
    }
    relations.push_back({v[0], v[1], Pose2{v[2], v[3], wrap_angle(v[7])}});
  }
  if (relations.empty()) {
    throw InputError(reader.name() + ": no relations (expected lines 't1 t2 x y z roll pitch yaw')");
  }
  return relations;
}

std::optional<std::size_t> find_scan_by_timestamp(const Scans& scans, double timestamp, double tolerance) {
  std::optional<std::size_t> best;
  double best_error = 0.0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const double error = std::abs(scans[i].timestamp - timestamp);
    if (error <= tolerance && (!best || error < best_error)) {
      best = i;
      best_error = error;
    }
  }
  return best;
}

nlohmann::json relations_error_json(const RelationsError& e) {
  if (e.relations == 0) return {{"relations", 0}, {"missing", e.missing}, {"note", "no relation matched"}};
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  return {{"translation_m", {{"mean", e.translation_mean}, {"std", e.translation_std}}},
          {"rotation_deg", {{"mean", e.rotation_mean * kDegrees}, {"std", e.rotation_std * kDegrees}}},
          {"relations", e.relations},
          {"missing", e.missing}};
}

}  // namespace partslam::io
