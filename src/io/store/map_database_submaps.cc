// MapDatabase: datasets and their submaps.
#include <nlohmann/json.hpp>

#include "io/store/map_database.h"
#include "io/store/map_database_internal.h"

namespace partslam::io {
namespace {

using internal::require_finite;
using sqlite::Statement;

// How a dataset's submaps were built: the SubmapConfig and where the scan poses came from.
std::string config_to_json(const DatasetSpec& spec) {
  const SubmapConfig& c = spec.config;
  nlohmann::json j = {{"window_length", c.window_length}, {"spacing", c.spacing},
                            {"resolution", c.resolution},       {"crop_size", c.crop_size},
                            {"max_range", c.max_range},         {"min_points", c.min_points},
                            {"align", c.align},                 {"scan_matched", spec.scan_matched}};
  if (spec.scan_matched) {
    j["scan_match_window"] = spec.front_end.matcher.linear_window;
    j["scan_match_turn"] = spec.front_end.matcher.angular_window;
  }
  return j.dump();
}

// Missing keys keep their defaults, so older files stay readable when SubmapConfig grows.
void config_from_json(const std::string& text, const std::string& context, DatasetSpec& spec) {
  SubmapConfig& c = spec.config;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (!j.is_object()) throw InputError("not a JSON object");
    c.max_range = j.value("max_range", c.max_range);
    spec.scan_matched = j.value("scan_matched", false);
    spec.front_end.matcher.linear_window = j.value("scan_match_window", spec.front_end.matcher.linear_window);
    spec.front_end.matcher.angular_window = j.value("scan_match_turn", spec.front_end.matcher.angular_window);
    validate(spec.front_end);
    c.window_length = j.value("window_length", c.window_length);
    c.spacing = j.value("spacing", c.spacing);
    c.resolution = j.value("resolution", c.resolution);
    c.crop_size = j.value("crop_size", c.crop_size);
    c.min_points = j.value("min_points", c.min_points);
    c.align = j.value("align", c.align);
    validate(c);
  } catch (const std::exception& e) {
    throw InputError(context + ": bad submap config '" + text + "': " + e.what());
  }
}

// A dataset with its counts: from dataset_counts (version 3), or by reading all its submaps (an older file opened
// read-only). `where` is "" or a WHERE clause on d.
std::string dataset_query(bool counted, const std::string& where) {
  if (counted) {
    // First and last map ids through the (dataset_id, idx) index; a missing counts row gives NULL (refused).
    return "SELECT d.id, d.name, d.source, d.kind, d.config, d.created, c.submaps,"
           " CASE WHEN c.submaps > 0 THEN CAST(c.points AS REAL) / c.submaps ELSE 0.0 END,"
           " COALESCE((SELECT id FROM submaps WHERE dataset_id = d.id ORDER BY idx LIMIT 1), -1),"
           " COALESCE((SELECT id FROM submaps WHERE dataset_id = d.id ORDER BY idx DESC LIMIT 1), -1)"
           " FROM datasets d LEFT JOIN dataset_counts c ON c.dataset_id = d.id " +
           where + " ORDER BY d.id";
  }
  return "SELECT d.id, d.name, d.source, d.kind, d.config, d.created, COUNT(s.id), COALESCE(AVG(s.point_count), 0),"
         " COALESCE(MIN(s.id), -1), COALESCE(MAX(s.id), -1) FROM datasets d LEFT JOIN submaps s"
         " ON s.dataset_id = d.id " +
         where + " GROUP BY d.id ORDER BY d.id";
}

DatasetInfo read_dataset(const Statement& q, const std::string& file) {
  DatasetInfo info;
  info.id = q.int64(0);
  const std::string context = file + ": dataset " + std::to_string(info.id);
  info.spec.name = q.text(1);
  info.spec.source = q.text(2);
  try {
    info.spec.kind = parse_dataset_kind(q.text(3));
  } catch (const InputError& e) {
    throw InputError(context + ": " + e.what());
  }
  config_from_json(q.text(4), context, info.spec);
  info.created = q.text(5);
  if (q.is_null(6) || q.int64(6) < 0) throw InputError(context + ": its counts are missing or negative (corrupt database)");
  info.submap_count = q.int64(6);
  info.mean_points = q.real(7);
  info.first_map_id = q.int64(8);
  info.last_map_id = q.int64(9);
  return info;
}

// The submap's stored numbers must be finite (SQLite would store NaN as NULL; inf breaks every later step).
void require_finite_numbers(const Submap& m, const std::string& context) {
  require_finite(m.anchor_timestamp, context, "anchor_timestamp");
  require_finite(m.travel, context, "travel");
  require_finite(m.alignment_angle, context, "alignment_angle");
  require_finite(m.T_world_map.x, context, "T_world_map.x");
  require_finite(m.T_world_map.y, context, "T_world_map.y");
  require_finite(m.T_world_map.theta, context, "T_world_map.theta");
}

// The columns read_submap reads; a file before schema version 4 has no origins (read as none).
std::string submap_columns(int schema_version) {
  return std::string("id, anchor_scan, anchor_timestamp, travel, alignment_angle, world_x, world_y, world_theta,"
                     " point_count, points, scan_timestamps, ") +
         (schema_version >= 4 ? "origins" : "x''");
}

Submap read_submap(const Statement& q, const std::string& file) {
  Submap m;
  m.id = q.int64(0);
  const std::string context = file + ": map " + std::to_string(m.id);
  m.anchor_scan = q.int64(1);
  m.anchor_timestamp = q.real(2);
  m.travel = q.real(3);
  m.alignment_angle = q.real(4);
  m.T_world_map = Pose2{q.real(5), q.real(6), q.real(7)};
  try {  // written finite (add_submaps checks), so anything else was edited in
    require_finite_numbers(m, context);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (corrupt database)");
  }
  const std::int64_t count = q.int64(8);
  if (count < 0) throw InputError(context + ": negative point count (corrupt database)");
  m.points = decode_points_f32(q.blob(9), static_cast<std::size_t>(count), context);
  internal::require_plausible(m.points, context);
  m.scan_timestamps = decode_f64(q.blob(10), context + " scan_timestamps");
  const auto origins = q.blob(11);
  if (origins.size() % 8 != 0) {
    throw InputError(context + ": origins blob holds " + std::to_string(origins.size()) +
                     " bytes, not whole points (corrupt database)");
  }
  m.origins = decode_points_f32(origins, origins.size() / 8, context + " origins");
  internal::require_plausible(m.origins, context + " origins");
  return m;
}

}  // namespace

std::int64_t MapDatabase::add_dataset(const DatasetSpec& spec) {
  require_writable();
  internal::require_name(spec.name, "dataset");
  try {
    validate(spec.config);
  } catch (const InputError& e) {
    throw InputError("dataset '" + spec.name + "': " + e.what());
  }
  if (const auto existing = find_dataset(spec.name)) {
    throw InputError(path().string() + ": a dataset named '" + spec.name + "' already exists (id " +
                     std::to_string(existing->id) + ")");
  }
  Statement insert(impl_->db,
                   "INSERT INTO datasets (name, source, kind, config, created) "
                   "VALUES (?1, ?2, ?3, ?4, strftime('%Y-%m-%dT%H:%M:%SZ', 'now')) RETURNING id");
  insert.bind_text(1, spec.name).bind_text(2, spec.source).bind_text(3, to_string(spec.kind));
  insert.bind_text(4, config_to_json(spec));
  insert.step();
  const std::int64_t id = insert.int64(0);
  insert.run();
  return id;
}

std::vector<std::int64_t> MapDatabase::add_submaps(std::int64_t dataset_id, const Submaps& submaps) {
  Transaction transaction(*this);
  const DatasetInfo info = dataset(dataset_id);
  Statement next(impl_->db, "SELECT COALESCE(MAX(idx) + 1, 0) FROM submaps WHERE dataset_id = ?1");
  next.bind_int(1, dataset_id).step();
  std::int64_t index = next.int64(0);
  Statement insert(
      impl_->db,
      "INSERT INTO submaps (dataset_id, idx, anchor_scan, anchor_timestamp, travel, alignment_angle,"
      " world_x, world_y, world_theta, point_count, points, scan_timestamps, origins)"
      " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13) RETURNING id");
  std::vector<std::int64_t> ids;
  ids.reserve(submaps.size());
  for (std::size_t i = 0; i < submaps.size(); ++i) {
    const Submap& m = submaps[i];
    const std::string context = "dataset '" + info.spec.name + "' submap " + std::to_string(i);
    require_finite_numbers(m, context);
    insert.reset();
    insert.bind_int(1, dataset_id).bind_int(2, index++).bind_int(3, m.anchor_scan);
    insert.bind_real(4, m.anchor_timestamp).bind_real(5, m.travel).bind_real(6, m.alignment_angle);
    insert.bind_real(7, m.T_world_map.x).bind_real(8, m.T_world_map.y).bind_real(9, m.T_world_map.theta);
    insert.bind_int(10, static_cast<std::int64_t>(m.points.size()));
    insert.bind_blob(11, encode_points_f32(m.points, context));
    insert.bind_blob(12, encode_f64(m.scan_timestamps));
    insert.bind_blob(13, encode_points_f32(m.origins, context + " origins"));
    insert.step();
    ids.push_back(insert.int64(0));
    insert.run();
  }
  transaction.commit();
  return ids;
}

std::int64_t MapDatabase::store_dataset(const DatasetSpec& spec, const Submaps& submaps) {
  Transaction transaction(*this);
  const std::int64_t id = add_dataset(spec);
  add_submaps(id, submaps);
  transaction.commit();
  return id;
}

void MapDatabase::remove_dataset(std::int64_t dataset_id) {
  Transaction transaction(*this);
  dataset(dataset_id);  // throws when missing
  Statement remove(impl_->db, "DELETE FROM datasets WHERE id = ?1");
  remove.bind_int(1, dataset_id).run();
  transaction.commit();
}

std::vector<DatasetInfo> MapDatabase::datasets() const {
  Statement q(impl_->db, dataset_query(keeps_counts(), ""));
  std::vector<DatasetInfo> out;
  while (q.step()) out.push_back(read_dataset(q, path().string()));
  return out;
}

DatasetInfo MapDatabase::dataset(std::int64_t dataset_id) const {
  Statement q(impl_->db, dataset_query(keeps_counts(), "WHERE d.id = ?1"));
  if (!q.bind_int(1, dataset_id).step()) {
    throw InputError(path().string() + ": no dataset with id " + std::to_string(dataset_id));
  }
  return read_dataset(q, path().string());
}

std::optional<DatasetInfo> MapDatabase::find_dataset(const std::string& name) const {
  Statement q(impl_->db, dataset_query(keeps_counts(), "WHERE d.name = ?1"));
  if (!q.bind_text(1, name).step()) return std::nullopt;
  return read_dataset(q, path().string());
}

std::vector<std::int64_t> MapDatabase::map_ids(std::int64_t dataset_id) const {
  Statement q(impl_->db, "SELECT id FROM submaps WHERE dataset_id = ?1 ORDER BY idx");
  q.bind_int(1, dataset_id);
  std::vector<std::int64_t> ids;
  while (q.step()) ids.push_back(q.int64(0));
  return ids;
}

Submaps MapDatabase::load_submaps(std::int64_t dataset_id) const {
  dataset(dataset_id);  // throws when missing
  Statement q(impl_->db,
              "SELECT " + submap_columns(impl_->schema_version) + " FROM submaps WHERE dataset_id = ?1 ORDER BY idx");
  q.bind_int(1, dataset_id);
  Submaps out;
  while (q.step()) out.push_back(read_submap(q, path().string()));
  return out;
}

Submap MapDatabase::load_submap(std::int64_t map_id) const {
  Statement q(impl_->db, "SELECT " + submap_columns(impl_->schema_version) + " FROM submaps WHERE id = ?1");
  if (!q.bind_int(1, map_id).step()) {
    throw InputError(path().string() + ": no map with id " + std::to_string(map_id));
  }
  return read_submap(q, path().string());
}

MapLocation MapDatabase::locate(std::int64_t map_id) const {
  Statement q(impl_->db,
              "SELECT s.dataset_id, d.name, s.idx FROM submaps s JOIN datasets d ON d.id = s.dataset_id "
              "WHERE s.id = ?1");
  if (!q.bind_int(1, map_id).step()) {
    throw InputError(path().string() + ": no map with id " + std::to_string(map_id));
  }
  return {map_id, q.int64(0), q.text(1), q.int64(2)};
}

}  // namespace partslam::io
