// partslam match DB --query ID --method SPEC: the online half of PartSLAM (docs/DESIGN.md, "Schemes"). Ranks every
// other stored map of the query's dataset (or, with --all, of every submaps dataset) for the query map — or, with
// --query-log LOG and a stretch (apps/query_options.h) or --query-points FILE, for a new local map built as the stored ones were, against every
// submaps dataset — through the library's one ranking entry point (core/matching/ranking.h), for any registered
// method (a new local map: the point-based ones):
//   dmm, dmm-ransac, dmm-exhaustive  Eq. 1 on the stored points; prints inliers, their share and T_map_query
//   succinct, grid, sc               built from the stored points at run time
//   imm:K, hmm:K                     the stored K-part descriptors (the query's stored P-part list for hMM)
//   rerank:R[:SPEC]                  SPEC ranks, its top R are reordered by dMM (with poses)
// For a pose, the implied world offset compares where the match puts the query (T_world_map * T_map_query)
// with the query's own stored pose; "dist" is the stored distance between the two maps' centres.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <span>

#include "apps/commands.h"
#include "apps/json_text.h"
#include "apps/cpd_options.h"
#include "apps/mpi_split.h"
#include "apps/query_options.h"
#include "io/descriptor_store.h"
#include "core/matching/localizer.h"  // kConfidentLocalization: the confidence called confident
#include "core/matching/ranking.h"
#include "core/parts/descriptor_layout.h"
#include "core/error.h"
#include "core/timing.h"
#include "core/matching/method_spec.h"
#include "io/atomic_file.h"
#include "io/map_database.h"
#include "plot/answer_image.h"

namespace partslam::apps {
namespace {

struct MatchOptions {
  std::string db;
  std::int64_t query = -1;
  QueryOptions new_query;  ///< a new local map from a log or a point file, instead of a stored one
  std::string json;
  std::string plot;
  std::string method = "dmm";
  int top = 10;
  std::string dictionary;
  bool all = false;
  double min_gap = 0;
  int query_parts = 0;
  int threads = 1;
  double gate = kDefaultOriginGate;
  DmmConfig dmm;
  DmmRansacConfig ransac;
};

// What the ranking's columns mean (printed under the table and in --help; the README says the same).
constexpr const char* kPoseColumns =
    "x, y, th: T_map_query, the query's frame in the stored map's frame (dMM's relative pose); dx, dy, dth: where "
    "that puts the query in the dataset's world frame (T_world_map * T_map_query) minus the query's own stored pose "
    "(0 for a correct match of a stored query)";
constexpr const char* kDistColumn =
    "dist: the stored distance between the query's and the map's centres in the dataset's world frame";
constexpr const char* kNewMapDash =
    "-: a new local map has no pose in the stored dataset's world frame (its log's or file's frame is another "
    "one), so dx, dy, dth and dist cannot be given; x, y, th are its pose in the stored map";
constexpr const char* kOtherDatasetDash =
    "-: dx, dy, dth and dist need the query and the map in the same dataset's world frame; this map is in another "
    "dataset";
constexpr const char* kRerankDash = "-: rerank scores only its top R by dMM; the rows below have no inliers or pose";

struct Candidate {
  const Submap* map = nullptr;
  std::string dataset;
};

struct Row {
  std::size_t candidate = 0;
  double score = 0;  // ranking key
  std::optional<double> descriptor_score;
  std::optional<DmmResult> dmm;
};

// The dictionary whose descriptors to read: the one named (which must have descriptors or be stored), else
// the only one with descriptors.
std::string resolve_descriptor_dictionary(const io::MapDatabase& db, const std::string& name) {
  std::set<std::string> names;
  for (const io::DescriptorSetInfo& s : db.descriptor_sets()) names.insert(s.dictionary);
  if (!name.empty()) {
    if (!names.count(name)) db.load_dictionary(name);  // throws "no dictionary named ..." when it is unknown
    return name;
  }
  if (names.empty()) {
    throw InputError(db.path().string() + ": no descriptors stored: run 'partslam describe " +
                     db.path().string() + " --dict NAME' first");
  }
  if (names.size() > 1)
    throw InputError(db.path().string() + ": descriptors of several dictionaries: choose --dict");
  return *names.begin();
}

// The stored parts the method reads: every candidate's K-part descriptor, and the query's (its K-part
// descriptor for iMM, its stored P-part list for hMM). `query_parts` gets the query's parts.
std::vector<std::vector<Part>> stored_parts(const io::MapDatabase& db, const Submap& query,
                                            const std::vector<Candidate>& candidates, const MethodSpec& method,
                                            const MatchOptions& o, std::vector<Part>& query_parts,
                                            std::string& timing) {
  const std::string dictionary = resolve_descriptor_dictionary(db, o.dictionary);
  const int k = method.parts;
  const auto t0 = Clock::now();
  std::map<std::int64_t, MapDescriptor> stored = io::load_descriptor_set(db, dictionary, k);
  std::vector<std::vector<Part>> parts;
  std::size_t missing = 0;
  for (const Candidate& c : candidates) {
    auto it = stored.find(c.map->id);
    if (it == stored.end()) {
      ++missing;
    } else {
      parts.push_back(std::move(it->second.parts));
    }
  }
  if (missing > 0) {
    throw InputError(std::to_string(missing) + " of " + std::to_string(candidates.size()) +
                     " maps have no K=" + std::to_string(k) + " descriptor for dictionary '" +
                     dictionary + "': " + io::describe_hint(db, dictionary, k));
  }
  const MethodSpec& parts_method = method.stages.empty() ? method : method.stages.front();
  const bool imm = parts_method.name == "imm";
  const int query_k = imm                 ? k
                      : o.query_parts > 0 ? o.query_parts
                                          : io::query_list_parts(db, dictionary, query.id);
  if (query_k == 0) {
    throw InputError("map " + std::to_string(query.id) +
                     " has no hMM query list (a descriptor of more than " +
                     std::to_string(kMaxUnscoredParts) + " parts) for dictionary '" + dictionary +
                     "': run 'partslam describe " + db.path().string() + " --dict " + dictionary +
                     "' first (it stores the P-part list as K = P when P > " +
                     std::to_string(kMaxUnscoredParts) + "), or name a stored list with --query-parts");
  }
  std::optional<MapDescriptor> query_descriptor = io::load_descriptor(db, dictionary, query_k, query.id);
  if (!query_descriptor) {
    throw InputError("the query map " + std::to_string(query.id) + " has no K=" + std::to_string(query_k) +
                     " descriptor for dictionary '" + dictionary +
                     "': " + io::describe_hint(db, dictionary, query_k));
  }
  query_parts = std::move(query_descriptor->parts);
  char buf[200];
  std::snprintf(buf, sizeof buf, "dictionary '%s', query %zu parts (K=%d), descriptors %.1f ms; ",
                dictionary.c_str(), query_parts.size(), query_k, ms_since(t0));
  timing += buf;
  if (query_parts.empty()) {
    timing += "note: CPD found no part of the query map, so every descriptor score is 0 (try 'describe --mc "
              "inlier'); ";
  }
  return parts;
}

void print_row(std::size_t rank, const Row& row, const Candidate& c, const Submap& query,
               const std::string& dataset, bool all, bool pose) {
  char buf[400];
  int len = std::snprintf(buf, sizeof buf, "%5zu %7lld", rank, static_cast<long long>(c.map->id));
  auto add = [&](const char* fmt, auto... v) {
    len += std::snprintf(buf + len, sizeof buf - static_cast<std::size_t>(len), fmt, v...);
  };
  if (all) add(" %12.12s", c.dataset.c_str());
  if (row.descriptor_score) add(" %10.4f", *row.descriptor_score);
  const bool same_world = c.dataset == dataset;
  if (row.dmm) {
    const DmmResult& r = *row.dmm;
    const Pose2& T = r.T_map_query;
    add(" %7d %5.1f  %7.2f %7.2f %8.1f", r.inliers, 100 * r.inlier_fraction, T.x, T.y,
        T.theta * 180 / std::numbers::pi);
    if (same_world) {
      const Pose2 implied = c.map->T_world_map * T;
      add("  %7.2f %7.2f %8.1f", implied.x - query.T_world_map.x, implied.y - query.T_world_map.y,
          wrap_angle(implied.theta - query.T_world_map.theta) * 180 / std::numbers::pi);
    } else {
      add("  %7s %7s %8s", "-", "-", "-");
    }
  } else if (pose) {  // a rerank row below the top R
    add(" %7s %5s  %7s %7s %8s  %7s %7s %8s", "-", "-", "-", "-", "-", "-", "-", "-");
  }
  if (same_world) {
    add(" %8.2f", (c.map->T_world_map.translation() - query.T_world_map.translation()).norm());
  } else {
    add(" %8s", "-");
  }
  std::cout << buf << "\n";
}

// The query's new local map (a log's stretch or a point file), built with the stored maps' submap settings (the
// first submaps dataset's).
Submap local_map(const io::MapDatabase& db, const MatchOptions& o, std::string& label) {
  std::optional<io::DatasetInfo> dataset;
  for (const io::DatasetInfo& d : db.datasets())
    if (d.spec.kind == io::DatasetKind::kSubmaps && !dataset) dataset = d;
  if (!dataset) throw InputError(db.path().string() + ": no submaps stored to match against");
  const QueryLog log = o.new_query.log.empty()
                           ? QueryLog{}
                           : load_query_log(o.new_query, dataset->spec.front_end, dataset->spec.config.window_length);
  const Submap m = build_query(o.new_query, log, dataset->spec.config, label);
  label += ", settings of '" + dataset->spec.name + "'";
  return m;
}

// A candidate more than 4 m from `best`'s frame, or in another dataset.
bool is_far(const Candidate& c, const Candidate& best) {
  return c.dataset != best.dataset ||
         (c.map->T_world_map.translation() - best.map->T_world_map.translation()).norm() > 4.0;
}

// How far the best dMM match beats the best one elsewhere: its inlier share minus the best inlier share among
// the candidates more than 4 m from it (is_far); nullopt without dMM. `scored` are the rows this process ranked
// (candidates [first, first + scored.size())); under mpirun every rank's share is gathered. Plain dMM ranked
// for its top k leaves the maps that could not enter it unscored, so their best is found exactly by a top-1
// search over them (the same for any threads and ranks); other methods' dMM rows are all exact.
std::optional<double> match_confidence(const std::vector<Row>& rows, const std::vector<Row>& scored,
                                       const std::vector<Candidate>& candidates, std::size_t first,
                                       const MethodSpec& method, const Ranker& ranker, const MapView& query,
                                       int threads, const WorkSplit& split) {
  if (rows.empty() || !rows.front().dmm) return std::nullopt;
  const Candidate& best = candidates[rows.front().candidate];
  double mine = 0.0;
  if (method.name == "dmm") {
    std::vector<std::size_t> far;
    for (std::size_t j = 0; j < scored.size(); ++j)
      if (is_far(candidates[first + j], best)) far.push_back(j);
    if (!far.empty()) {
      const Ranking r = ranker.rank(query, far, {threads, 1});
      for (const auto& d : r.direct)
        if (d && d->exact) mine = std::max(mine, d->inlier_fraction);
    }
  } else {
    for (const Row& r : scored)
      if (r.dmm && is_far(candidates[r.candidate], best)) mine = std::max(mine, r.dmm->inlier_fraction);
  }
  double elsewhere = 0.0;
  for (double e : all_gather<double>(split, {&mine, 1})) elsewhere = std::max(elsewhere, e);
  return rows.front().dmm->inlier_fraction - elsewhere;
}

// mpirun -n P: methods whose score of a stored map depends on that map and the query alone can be sharded;
// `succinct` (and `grid` with hub=) learns a hubness term from all stored maps, and a two-stage method would
// shortlist per rank, so neither would give the serial ranking.
bool shardable(const MethodSpec& method) {
  if (!method.stages.empty() || method.name == "succinct") return false;
  return method.name != "grid" || method.spec.find(":hub=") == std::string::npos;
}

// A Row as it travels between ranks (merge_shards): a plain record, its optionals as a flag and a value. Of a
// dMM result, the inliers, their fraction and the pose travel.
struct ShardRow {
  std::size_t candidate = 0;
  double score = 0;
  bool has_descriptor_score = false;
  double descriptor_score = 0;
  bool has_dmm = false;
  int inliers = 0;
  double inlier_fraction = 0;
  Pose2 T_map_query;
};

ShardRow to_shard_row(const Row& row) {
  const DmmResult d = row.dmm.value_or(DmmResult{});
  return {row.candidate,
          row.score,
          row.descriptor_score.has_value(),
          row.descriptor_score.value_or(0.0),
          row.dmm.has_value(),
          d.inliers,
          d.inlier_fraction,
          d.T_map_query};
}

Row from_shard_row(const ShardRow& s) {
  Row row;
  row.candidate = s.candidate;
  row.score = s.score;
  if (s.has_descriptor_score) row.descriptor_score = s.descriptor_score;
  if (s.has_dmm) {
    DmmResult d;
    d.inliers = s.inliers;
    d.inlier_fraction = s.inlier_fraction;
    d.T_map_query = s.T_map_query;
    row.dmm = d;
  }
  return row;
}

// The rows every rank found best in its slice (at most `top` each), merged in the serial order: score
// descending, then candidate (a serial run sorts the candidates stably by score). Rows travel as ShardRows.
std::vector<Row> merge_shards(const std::vector<Row>& mine, std::size_t top, const WorkSplit& split) {
  std::vector<ShardRow> sent;
  for (std::size_t r = 0; r < std::min(top, mine.size()); ++r) sent.push_back(to_shard_row(mine[r]));
  std::vector<Row> rows;
  for (const ShardRow& s : all_gather<ShardRow>(split, sent)) rows.push_back(from_shard_row(s));
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
    return a.score != b.score ? a.score > b.score : a.candidate < b.candidate;
  });
  return rows;
}

nlohmann::json ranking_json(const std::string& query, const MethodSpec& method, const std::vector<Row>& rows,
                            const std::vector<Candidate>& candidates, std::size_t shown,
                            const std::optional<double>& confidence) {
  nlohmann::json out = {{"query", query}, {"method", method.spec}, {"candidates", candidates.size()}};
  if (confidence) out["confidence"] = *confidence;
  out["ranking"] = nlohmann::json::array();
  for (std::size_t r = 0; r < shown; ++r) {
    const Row& row = rows[r];
    const Candidate& c = candidates[row.candidate];
    nlohmann::json j = {{"rank", r + 1}, {"map", c.map->id}, {"dataset", c.dataset}};
    if (row.descriptor_score) j["descriptor_score"] = *row.descriptor_score;
    if (row.dmm) {
      const Pose2& T = row.dmm->T_map_query;
      j["inliers"] = row.dmm->inliers;
      j["inlier_fraction"] = row.dmm->inlier_fraction;
      j["T_map_query"] = {{"x", T.x}, {"y", T.y}, {"theta", T.theta}};
    }
    out["ranking"].push_back(j);
  }
  return out;
}

// --plot: the best stored maps (up to three), each with the query's points where the match puts them (green on
// the first when the match is confident, else orange); a method without poses draws the stored maps alone.
void write_match_plot(const std::string& path, const Submap& query, const std::vector<Row>& rows,
                      const std::vector<Candidate>& candidates, std::size_t shown,
                      const std::optional<double>& confidence) {
  std::vector<plot::Panel> panels;
  for (std::size_t r = 0; r < std::min<std::size_t>(shown, 3); ++r) {
    const Row& row = rows[r];
    const Candidate& c = candidates[row.candidate];
    plot::Panel panel;
    panel.layers.push_back({c.map->points, plot::kMapGrey, 1.2});
    char title[200];
    int len = std::snprintf(title, sizeof title, "#%zu: map %lld (%s)", r + 1, static_cast<long long>(c.map->id),
                            c.dataset.c_str());
    if (row.dmm) {
      const bool sure = r == 0 && confidence && *confidence >= kConfidentLocalization;
      panel.layers.push_back({plot::transformed(query.points, row.dmm->T_map_query),
                              sure ? plot::kGood : plot::kDoubtful, 1.5});
      len += std::snprintf(title + len, sizeof title - static_cast<std::size_t>(len), ", %.0f %% inliers",
                           100 * row.dmm->inlier_fraction);
      if (r == 0 && confidence)
        std::snprintf(title + len, sizeof title - static_cast<std::size_t>(len), ", confidence %.2f", *confidence);
    } else {
      std::snprintf(title + len, sizeof title - static_cast<std::size_t>(len), ", score %.3g (no pose)", row.score);
    }
    panel.title = title;
    panels.push_back(std::move(panel));
  }
  for (plot::Panel& p : panels) p.legend = "grey: stored map; green / orange: the query (confident / not)";
  plot::write_panels_png(path, panels, 500);
  std::cout << "wrote " << path << "\n";
}

void run_match(const MatchOptions& o) {
  const MethodSpec method = parse_method_spec(o.method);
  if (o.top < 1) throw InputError("--top must be >= 1, got " + std::to_string(o.top));
  if (o.threads < 1 || o.threads > 1024) throw InputError("--threads must be in [1, 1024]");
  if (!(o.min_gap >= 0) || !std::isfinite(o.min_gap))
    throw InputError("--min-gap must be a finite number >= 0 [m], got " + std::to_string(o.min_gap));
  if (o.query_parts < 0 || o.query_parts > 10000)
    throw InputError("--query-parts must be in [0, 10000] (0: the longest stored list), got " +
                     std::to_string(o.query_parts));
  validate(o.dmm);
  validate(o.ransac);
  const bool new_map = o.new_query.given();
  if ((o.query >= 0) == new_map)
    throw InputError("give either --query ID (a stored map) or --query-log LOG / --query-points FILE (a new local map)");
  check_query_options(o.new_query);
  if (!new_map && (o.new_query.stretch_given() || o.new_query.scan_match))
    throw InputError("--from-m, --to-m, --at-m, --from-time, --to-time, --at and --scan-match go with --query-log, "
                     "not --query ID");
  if (new_map && method.needs_parts)
    throw InputError("a new local map: method '" + o.method + "' needs the query's CPD parts; use a point-based one "
                     "(dmm, succinct, grid, sc, rerank:R)");
  if (!o.json.empty()) io::check_writable(o.json);
  if (!o.plot.empty()) io::check_writable(o.plot);
  const WorkSplit& split = world_split();
  if (split.size() > 1 && !shardable(method))
    throw InputError("mpirun: method '" + o.method + "' cannot be sharded (it learns from all stored maps or "
                     "shortlists per rank); use dmm, dmm-ransac, imm, hmm, sc or grid without hub=, or one process");
  const auto t_start = Clock::now();
  const io::MapDatabase db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kReadOnly);
  io::MapLocation where;
  std::string query_label;
  const Submap query = new_map ? local_map(db, o, query_label) : db.load_submap(o.query);
  if (!new_map) {
    where = db.locate(o.query);
    query_label = "query map " + std::to_string(query.id) + " (dataset '" + where.dataset_name + "', submap " +
                  std::to_string(where.index) + ", " + std::to_string(query.points.size()) + " points)";
  }

  // The candidates: the query's dataset, or every submaps dataset.
  std::vector<std::pair<std::string, Submaps>> loaded;
  for (const io::DatasetInfo& d : db.datasets()) {
    const bool every = o.all || new_map;  // a new local map is ranked against every dataset
    if (d.id == where.dataset_id || (every && d.spec.kind == io::DatasetKind::kSubmaps))
      loaded.emplace_back(d.spec.name, db.load_submaps(d.id));
  }
  std::vector<Candidate> candidates;
  std::size_t too_recent = 0;
  for (const auto& [name, maps] : loaded) {
    for (const Submap& m : maps) {
      if (m.id == query.id) continue;
      if (name == where.dataset_name && std::abs(m.travel - query.travel) < o.min_gap) {
        ++too_recent;
        continue;
      }
      candidates.push_back({&m, name});
    }
  }
  const double load_ms = ms_since(t_start);
  if (candidates.empty()) throw InputError("match: no other map to rank for map " + std::to_string(o.query));

  std::string timing;
  std::vector<Part> query_parts;
  std::vector<std::vector<Part>> parts;
  if (method.needs_parts) parts = stored_parts(db, query, candidates, method, o, query_parts, timing);
  std::vector<MapView> views(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    views[i].points = &candidates[i].map->points;
    if (method.needs_parts) views[i].parts = &parts[i];
  }
  RankingConfig config;
  config.dmm = o.dmm;
  config.ransac = o.ransac;
  config.origin_gate = o.gate;
  config.hmm_query_parts = std::max<int>(1, static_cast<int>(query_parts.size()));
  // This process's slice of the candidates (all of them outside mpirun): prepared and ranked here.
  const auto [first, last] = split.slice(candidates.size());
  const std::span<const MapView> mine(views.data() + first, last - first);
  auto t0 = Clock::now();
  const std::unique_ptr<Ranker> ranker = make_ranker(method, config);
  ranker->prepare(mine, o.threads);
  const double prepare_ms = ms_since(t0);
  std::vector<std::size_t> everyone(mine.size());
  for (std::size_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  const Ranking ranking = ranker->rank({&query.points, &query_parts}, everyone, {o.threads, o.top});
  char buf[240];
  std::snprintf(buf, sizeof buf, "prepare %.1f ms (offline), query %.2f ms, ranking %.2f ms (%.3f ms per map)%s",
                prepare_ms, ranking.prep_ms, ranking.match_ms,
                ranking.match_ms / static_cast<double>(std::max<std::size_t>(1, mine.size())),
                split.size() > 1 ? " on rank 0's slice" : "");
  timing += buf;
  std::vector<Row> rows(mine.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].candidate = first + i;
    rows[i].score = ranking.scores[i];
    if (!ranking.direct.empty()) rows[i].dmm = ranking.direct[i];
    if (!ranking.shortlist_scores.empty()) {
      rows[i].descriptor_score = ranking.shortlist_scores[i];
    } else if (ranking.direct.empty()) {
      rows[i].descriptor_score = ranking.scores[i];
    }
  }
  std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.score > b.score; });
  const std::vector<Row> scored = rows;
  if (split.size() > 1) rows = merge_shards(rows, static_cast<std::size_t>(o.top), split);
  const std::optional<double> confidence = match_confidence(rows, scored, candidates, first, method, *ranker,
                                                            {&query.points, &query_parts}, o.threads, split);
  if (!is_reporting_process()) return;  // rank 0 prints and writes

  const bool all = o.all || new_map;
  std::cout << query_label << "; " << method.label() << " over " << candidates.size() << " maps"
            << (all ? " of every dataset" : " of its dataset");
  if (too_recent > 0) std::cout << " (" << too_recent << " within " << o.min_gap << " m of travel left out)";
  std::cout << "\n";
  const bool pose = method.needs_points;
  std::string header = " rank     map";
  if (all) header += "      dataset";
  if (!method.needs_points || !method.stages.empty()) {
    const MethodSpec& first = method.stages.empty() ? method : method.stages.front();
    char score[32];
    std::snprintf(score, sizeof score, " %10s", (first.name == "imm"   ? std::string("iMM score")
                                                 : first.name == "hmm" ? std::string("hMM score")
                                                                       : first.name + " score")
                                                    .c_str());
    header += score;
  }
  char columns[160];
  std::snprintf(columns, sizeof columns, " %7s %5s  %7s %7s %8s  %7s %7s %8s", "inliers", "inl%", "x [m]",
                "y [m]", "th [deg]", "dx [m]", "dy [m]", "dth[deg]");
  if (pose) header += columns;
  header += " dist [m]";
  std::cout << header << "\n";
  const std::size_t shown = std::min<std::size_t>(rows.size(), static_cast<std::size_t>(o.top));
  bool other_world = false, below_rerank = false;
  for (std::size_t r = 0; r < shown; ++r) {
    const Candidate& c = candidates[rows[r].candidate];
    print_row(r + 1, rows[r], c, query, where.dataset_name, all, pose);
    other_world |= new_map || c.dataset != where.dataset_name;
    below_rerank |= pose && !rows[r].dmm;
  }
  if (pose) std::cout << kPoseColumns << "\n";
  std::cout << kDistColumn << "\n";
  if (other_world) std::cout << (new_map ? kNewMapDash : kOtherDatasetDash) << "\n";
  if (below_rerank) std::cout << kRerankDash << "\n";
  if (confidence) std::printf("confidence %.3f (the best dMM inlier share minus the best one more than 4 m away)\n", *confidence);
  std::cout << "time: load " << static_cast<long>(load_ms) << " ms; " << timing << "\n";
  if (!o.plot.empty()) write_match_plot(o.plot, query, rows, candidates, shown, confidence);
  if (!o.json.empty())
    io::write_atomically(o.json, [&](std::ostream& out) {
      out << json_text(ranking_json(query_label, method, rows, candidates, shown, confidence));
    });
}

}  // namespace

void register_match(CLI::App& app) {
  auto o = std::make_shared<MatchOptions>();
  CLI::App* cmd =
      app.add_subcommand("match", "Rank the stored maps for one query map (dMM, iMM, hMM, rerank)");
  cmd->add_option("db", o->db, "map database file")->required();
  cmd->add_option("--query", o->query, "global map id of a stored query map (see 'partslam info')");
  add_query_options(*cmd, o->new_query);
  cmd->add_option("--json", o->json, "write the ranking (map, dataset, scores, pose, confidence) as JSON");
  cmd->add_option(
         "--method", o->method, method_syntax_list())
      ->capture_default_str();
  cmd->add_option("--top", o->top, "rows of the ranking to print")->capture_default_str();
  cmd->add_option("--plot", o->plot,
                  "draw the best three stored maps as a PNG, each with the query's points at the found pose");
  cmd->add_option("--dict", o->dictionary,
                  "dictionary of the descriptors (default: the only one with descriptors)");
  cmd->add_flag("--all", o->all, "rank the maps of every submaps dataset, not only the query's");
  cmd->add_option(
         "--min-gap", o->min_gap,
         "leave out maps of the query's dataset within this travel of the query [m] (20 finds loop closures)")
      ->capture_default_str();
  cmd->add_option("--query-parts", o->query_parts,
                  "K of the stored hMM query list (default: the longest one)");
  cmd->add_option("--gate", o->gate,
                  "descriptor matcher: origin gate [m], part pairs must put the map frames this close; 0 = off "
                  "(the paper)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--dmm-dilation", o->dmm.dilation, "dMM: target dilation [cells]")->capture_default_str();
  cmd->add_option_function<double>(
         "--dmm-angular-window", [o](double deg) { o->dmm.angular_window = deg * std::numbers::pi / 180.0; },
         "dMM: residual rotation window about each quarter turn [deg]")
      ->default_str("3");
  cmd->add_option("--threads", o->threads, "threads (results do not depend on it)")->capture_default_str();
  cmd->footer(std::string("Columns: inliers, inl%: dMM's inlier count and share. ") + kPoseColumns + ". " +
              kDistColumn + ". " + kNewMapDash + ". " + kOtherDatasetDash + ". " + kRerankDash + ".");
  cmd->callback([o] { run_match(*o); });
}

}  // namespace partslam::apps
