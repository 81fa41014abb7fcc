// partslam match DB --query ID --method SPEC: the online half of PartSLAM (docs/DESIGN.md, "Schemes"). Ranks every
// other stored map of the query's dataset (or, with --all, of every submaps dataset) for the query map — or, with
// --query-log LOG and a stretch (apps/query_options.h) or --query-points FILE, for a new local map built as the stored ones were, against every
// submaps dataset — through the library's query entry point (core/ranking/query.h), for any registered method
// (a new local map: the point-based ones):
//   dmm, dmm-ransac, dmm-exhaustive  Eq. 1 on the stored points; prints inliers, their share and T_map_query
//   succinct, grid, sc               built from the stored points at run time
//   imm:K, hmm:K                     the stored K-part descriptors (the query's stored P-part list for hMM)
//   rerank:R[:SPEC]                  SPEC ranks, its top R are reordered by dMM (with poses)
// For a pose, the implied world offset compares where the match puts the query (T_world_map * T_map_query)
// with the query's own stored pose; "dist" is the stored distance between the two maps' centres.
// Tested by: apps/cli_eval_test.cc, apps/cli_parts_test.cc, apps/cli_locate_test.cc
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <span>

#include "apps/commands.h"
#include "apps/cpd_options.h"
#include "apps/db_hints.h"
#include "apps/dmm_options.h"
#include "apps/json_text.h"
#include "apps/mpi_split.h"
#include "apps/query_options.h"
#include "core/error.h"
#include "core/matching/verification.h"  // pose_ambiguous
#include "core/parts/descriptor_layout.h"
#include "core/ranking/query.h"
#include "core/ranking/ranking.h"  // ranking_dmm_config
#include "core/timing.h"
#include "io/files/atomic_file.h"
#include "io/store/descriptor_store.h"
#include "io/store/map_database.h"
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
  DmmConfig dmm = ranking_dmm_config();  // eval's and the Python Ranker's search
  DmmRansacConfig ransac;
};

// What the ranking's columns mean (printed under the table and in --help; docs/USAGE.md says the same).
constexpr const char* kPoseColumns =
    "x, y, th: T_map_query, the query's frame in the stored map's frame (dMM's relative pose); dx, dy, dth: where "
    "that puts the query in the dataset's world frame (T_world_map * T_map_query) minus the query's own stored pose "
    "(0 for a correct match of a stored query)";
constexpr const char* kProbabilityColumn =
    "prob: the probability that the query and the map show the same place at that pose (the verified dMM)";
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

// A verified row whose map is as probable at another pose (VerifiedDmm::runner_up): its pose is not to be
// trusted.
bool ambiguous(const QueryRow& row) { return pose_ambiguous(row.probability, row.runner_up).value_or(false); }

void print_row(std::size_t rank, const QueryRow& row, const Candidate& c, const Submap& query,
               const std::string& dataset, bool all, bool pose, bool calibrated) {
  char buf[400];
  int len = std::snprintf(buf, sizeof buf, "%5zu %7lld", rank, static_cast<long long>(c.map->id));
  auto add = [&](const char* fmt, auto... v) {
    len += std::snprintf(buf + len, sizeof buf - static_cast<std::size_t>(len), fmt, v...);
  };
  if (all) add(" %12.12s", c.dataset.c_str());
  if (row.stage_score) add(" %10.4f", *row.stage_score);
  if (calibrated && row.probability) {
    add(" %6.3f", *row.probability);
  } else if (calibrated) {
    add(" %6s", "-");
  }
  const bool same_world = c.dataset == dataset;
  if (row.pose) {
    const DmmResult& r = *row.pose;
    const Pose2& T = r.T_map_query;
    add(" %7d %5.1f  %7.2f %7.2f %8.1f", r.inliers, 100 * r.inlier_fraction, T.x, T.y,
        T.theta * kDegreesPerRadian);
    if (same_world) {
      const Pose2 implied = c.map->T_world_map * T;
      add("  %7.2f %7.2f %8.1f", implied.x - query.T_world_map.x, implied.y - query.T_world_map.y,
          wrap_angle(implied.theta - query.T_world_map.theta) * kDegreesPerRadian);
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

void check_options(const MatchOptions& o, const MethodSpec& method) {
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
  if (!new_map && (o.new_query.stretch.given() || o.new_query.scan_match))
    throw InputError("--from-m, --to-m, --at-m, --from-time, --to-time, --at and --scan-match go with --query-log, "
                     "not --query ID");
  if (new_map && method.traits.needs_parts)
    throw InputError("a new local map: method '" + o.method + "' needs the query's CPD parts; use a point-based one "
                     "(dmm, succinct, grid, sc, rerank:R)");
  io::check_outputs({{"--json", o.json}, {"--plot", o.plot}},
                    {{"DB", o.db}, {"--query-log", o.new_query.log}, {"--query-points", o.new_query.points}});
  if (world_split().size() > 1 && !method.traits.shardable)
    throw InputError("mpirun: method '" + o.method + "' cannot be sharded (it learns from all stored maps or "
                     "shortlists per rank); use dmm, dmm-ransac, imm, hmm, sc or grid without hub=, or one process");
}

// The query and what to rank it against: the other maps of its dataset (--all, or a new local map: of every
// submaps dataset), leaving out those within --min-gap of travel.
struct Query {
  Submap map;
  io::MapLocation where;
  std::string label;
  bool new_map = false;
  std::vector<std::pair<std::string, Submaps>> loaded;
  std::vector<Candidate> candidates;
  std::size_t too_recent = 0;
};

void load_query(const io::MapDatabase& db, const MatchOptions& o, Query& q) {
  q.new_map = o.new_query.given();
  if (q.new_map) {
    q.map = local_map(db, o, q.label);
  } else {
    q.map = with_hint([&] { return db.load_submap(o.query); }, info_hint(o.db));
    q.where = db.locate(o.query);
    q.label = "query map " + std::to_string(q.map.id) + " (dataset '" + q.where.dataset_name + "', submap " +
              std::to_string(q.where.index) + ", " + std::to_string(q.map.points.size()) + " points)";
  }
  for (const io::DatasetInfo& d : db.datasets()) {
    const bool every = o.all || q.new_map;
    if (d.id == q.where.dataset_id || (every && d.spec.kind == io::DatasetKind::kSubmaps))
      q.loaded.emplace_back(d.spec.name, db.load_submaps(d.id));
  }
  std::vector<const Submaps*> datasets;
  std::optional<std::size_t> own;
  for (const auto& [name, maps] : q.loaded) {
    if (!q.new_map && name == q.where.dataset_name) own = datasets.size();
    datasets.push_back(&maps);
  }
  const CandidateChoice chosen = choose_candidates(q.map, datasets, own, o.min_gap);
  q.too_recent = chosen.too_recent;
  for (const ChosenMap& c : chosen.maps)
    q.candidates.push_back({&(*datasets[c.dataset])[c.map], q.loaded[c.dataset].first});
  if (q.candidates.empty()) throw InputError("match: no other map to rank for map " + std::to_string(o.query));
}

// The candidates as the query entry point sees them (points, parts where the method reads them, place: the
// position of their dataset in q.loaded).
std::vector<QueryCandidate> query_candidates(const Query& q, const io::RankingParts& parts) {
  std::vector<QueryCandidate> out;
  for (std::size_t i = 0; i < q.candidates.size(); ++i) {
    const Candidate& c = q.candidates[i];
    const auto dataset = std::find_if(q.loaded.begin(), q.loaded.end(), [&](const auto& d) { return d.first == c.dataset; });
    out.push_back({{&c.map->points, parts.stored.empty() ? nullptr : &parts.stored[i], &c.map->origins},
                   static_cast<int>(dataset - q.loaded.begin()), c.map->T_world_map});
  }
  return out;
}

nlohmann::json ranking_json(const Query& q, const MethodSpec& method, const QueryAnswer& answer) {
  nlohmann::json out = {{"query", q.label}, {"method", method.spec}, {"candidates", q.candidates.size()}};
  if (answer.confidence) {
    out["confidence"] = *answer.confidence;
    out["confidence_kind"] = answer.calibrated ? "probability" : "margin";
  }
  out["ranking"] = nlohmann::json::array();
  for (std::size_t r = 0; r < answer.rows.size(); ++r) {
    const QueryRow& row = answer.rows[r];
    const Candidate& c = q.candidates[row.candidate];
    nlohmann::json j = {{"rank", r + 1}, {"map", c.map->id}, {"dataset", c.dataset}};
    if (row.stage_score) j["descriptor_score"] = *row.stage_score;
    if (row.probability) j["probability"] = *row.probability;
    if (row.probability && row.runner_up) {
      j["runner_up_probability"] = *row.runner_up;
      j["pose_ambiguous"] = ambiguous(row);
    }
    if (row.pose) {
      const Pose2& T = row.pose->T_map_query;
      j["inliers"] = row.pose->inliers;
      j["inlier_fraction"] = row.pose->inlier_fraction;
      j["T_map_query"] = pose_json(T);
    }
    out["ranking"].push_back(j);
  }
  return out;
}

// --plot: the best stored maps (up to three), each with the query's points where the match puts them (green on
// the first when the match is confident, else orange); a method without poses draws the stored maps alone.
void write_match_plot(const std::string& path, const Query& q, const QueryAnswer& answer) {
  std::vector<plot::Panel> panels;
  for (std::size_t r = 0; r < std::min<std::size_t>(answer.rows.size(), 3); ++r) {
    const QueryRow& row = answer.rows[r];
    const Candidate& c = q.candidates[row.candidate];
    plot::Panel panel;
    panel.layers.push_back({c.map->points, plot::kMapGrey, 1.2});
    panel.title = "#" + std::to_string(r + 1) + ": map " + std::to_string(c.map->id) + " (" + c.dataset + ")";
    char text[120];
    if (row.pose) {
      const bool sure =
          r == 0 && answer.confidence &&
          ConfidenceRule{}.confident_answer(*answer.confidence, answer.calibrated) &&
          !ambiguous(row);
      panel.layers.push_back({plot::transformed(q.map.points, row.pose->T_map_query),
                              sure ? plot::kGood : plot::kDoubtful, 1.5});
      std::snprintf(text, sizeof text, ", %.0f %% inliers", 100 * row.pose->inlier_fraction);
      panel.title += text;
      if (r == 0 && answer.confidence) {
        std::snprintf(text, sizeof text, ", confidence %.2f", *answer.confidence);
        panel.title += text;
      }
    } else {
      std::snprintf(text, sizeof text, ", score %.3g (no pose)", row.score);
      panel.title += text;
    }
    panel.legend = "grey: stored map; green / orange: the query (confident / not)";
    panels.push_back(std::move(panel));
  }
  plot::write_panels_png(path, panels, 500);
  std::cout << "wrote " << path << "\n";
}

void print_table(const Query& q, const MethodSpec& method, const QueryAnswer& answer, bool all) {
  const bool pose = method.traits.gives_pose;
  std::string header = " rank     map";
  if (all) header += "      dataset";
  char text[160];
  if (!method.traits.stage_score.empty()) {
    std::snprintf(text, sizeof text, " %10s", method.traits.stage_score.c_str());
    header += text;
  }
  if (method.traits.calibrated) header += "   prob";
  std::snprintf(text, sizeof text, " %7s %5s  %7s %7s %8s  %7s %7s %8s", "inliers", "inl%", "x [m]", "y [m]",
                "th [deg]", "dx [m]", "dy [m]", "dth[deg]");
  if (pose) header += text;
  std::cout << header << " dist [m]\n";
  bool other_world = false, below_rerank = false;
  for (std::size_t r = 0; r < answer.rows.size(); ++r) {
    const Candidate& c = q.candidates[answer.rows[r].candidate];
    print_row(r + 1, answer.rows[r], c, q.map, q.where.dataset_name, all, pose, method.traits.calibrated);
    other_world |= q.new_map || c.dataset != q.where.dataset_name;
    below_rerank |= pose && !answer.rows[r].pose;
  }
  if (method.traits.calibrated) std::cout << kProbabilityColumn << "\n";
  if (pose) std::cout << kPoseColumns << "\n";
  std::cout << kDistColumn << "\n";
  if (other_world) std::cout << (q.new_map ? kNewMapDash : kOtherDatasetDash) << "\n";
  if (below_rerank) std::cout << kRerankDash << "\n";
  if (answer.confidence && answer.calibrated) {
    std::printf("confidence %.3f (the probability that the best map is the same place and the best one more than "
                "%.0f m away is not)\n",
                *answer.confidence, OtherPlace{}.distance);
  } else if (answer.confidence) {
    std::printf("confidence %.3f (the best dMM inlier share minus the best one more than %.0f m away)\n",
                *answer.confidence, OtherPlace{}.distance);
  }
  if (!answer.rows.empty() && ambiguous(answer.rows.front())) {
    const QueryRow& best = answer.rows.front();
    std::printf(
        "warning: the pose of map %lld is ambiguous: another pose of it has probability %.3f against the "
        "answer's %.3f (a corridor's half turn or shift); do not use that pose unchecked\n",
        static_cast<long long>(q.candidates[best.candidate].map->id), *best.runner_up, *best.probability);
  }
}

void run_match(const MatchOptions& o) {
  const MethodSpec method = parse_method_spec(o.method);
  check_options(o, method);
  const auto t_start = Clock::now();
  const io::MapDatabase db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kReadOnly);
  Query q;
  load_query(db, o, q);
  const double load_ms = ms_since(t_start);
  std::string timing;
  io::RankingParts parts;
  if (method.traits.needs_parts) {
    const std::string dictionary =
        with_hint([&] { return io::resolve_descriptor_dictionary(db, o.dictionary); }, describe_hint(o.db));
    std::vector<std::int64_t> ids;
    for (const Candidate& c : q.candidates) ids.push_back(c.map->id);
    parts = with_hint([&] { return io::load_ranking_parts(db, dictionary, method.traits, ids, q.map.id, o.query_parts); },
                      describe_hint(o.db) + "; --query-parts names a stored list");
    char buf[200];
    std::snprintf(buf, sizeof buf, "dictionary '%s', query %zu parts (K=%d), descriptors %.1f ms; ",
                  dictionary.c_str(), parts.query.size(), parts.query_k, parts.ms);
    timing += buf;
    if (parts.query.empty())
      timing += "note: CPD found no part of the query map, so every descriptor score is 0 (try 'describe --mc "
                "inlier'); ";
  }
  RankingConfig config;
  config.dmm = o.dmm;
  config.ransac = o.ransac;
  config.parts.origin_gate = o.gate;
  config.parts.hmm_query_parts = std::max<int>(1, static_cast<int>(parts.query.size()));
  const std::vector<QueryCandidate> candidates = query_candidates(q, parts);
  const QueryAnswer answer = rank_query(method, config, candidates, {&q.map.points, &parts.query, &q.map.origins},
                                        {static_cast<std::size_t>(o.top), o.threads, OtherPlace{}}, world_split());
  if (!is_reporting_process()) return;  // rank 0 prints and writes
  char buf[240];
  std::snprintf(buf, sizeof buf, "prepare %.1f ms (offline), query %.2f ms, ranking %.2f ms (%.3f ms per map)%s",
                answer.prepare_ms, answer.prep_ms, answer.match_ms,
                answer.match_ms / static_cast<double>(std::max<std::size_t>(1, answer.ranked_here)),
                world_split().size() > 1 ? " on rank 0's slice" : "");
  timing += buf;
  const bool all = o.all || q.new_map;
  std::cout << q.label << "; " << method.label << " over " << q.candidates.size() << " maps"
            << (all ? " of every dataset" : " of its dataset");
  if (q.too_recent > 0) std::cout << " (" << q.too_recent << " within " << o.min_gap << " m of travel left out)";
  std::cout << "\n";
  print_table(q, method, answer, all);
  std::cout << "time: load " << static_cast<long>(load_ms) << " ms; " << timing << "\n";
  if (!o.plot.empty()) write_match_plot(o.plot, q, answer);
  if (!o.json.empty())
    io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(ranking_json(q, method, answer)); });
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
  cmd->add_option(
         "--gate", o->gate,
         "descriptor matcher: origin gate [m], part pairs must put the map frames this close; 0 = off "
         "(the paper)")
      ->capture_default_str()
      ->check(in_range(0.0, 1000.0));
  add_dmm_options(*cmd, o->dmm);
  cmd->add_option("--threads", o->threads, "threads (results do not depend on it)")->capture_default_str();
  cmd->footer(std::string("Columns: inliers, inl%: dMM's inlier count and share. ") + kPoseColumns + ". " +
              kDistColumn + ". " + kNewMapDash + ". " + kOtherDatasetDash + ". " + kRerankDash + ".");
  cmd->callback([o] { run_match(*o); });
}

}  // namespace partslam::apps
