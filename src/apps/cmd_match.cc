// partslam match DB --query ID [--method dmm|dmm-ransac|dmm-exhaustive] [--top K]: ranks the stored submaps
// against one of them by direct map matching (Eq. 1) and prints the best K with their inlier counts and the
// relative pose T_map_query (maps query-frame points into the stored map's frame). dmm with --top K > 0 uses
// top-k pruning (maps that cannot enter the top K are dropped early); --top 0 ranks every map exactly.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "core/dmm.h"
#include "core/dmm_ransac.h"
#include "core/error.h"
#include "core/method_spec.h"
#include "io/atomic_file.h"
#include "io/map_database.h"

namespace partslam::apps {
namespace {

struct MatchOptions {
  std::string file;
  std::int64_t query = -1;
  std::string method = "dmm";
  int top = 10;
  std::string dataset;  // empty: every submap dataset
  bool include_self = false;
  int threads = 1;
  DmmConfig dmm;
  DmmRansacConfig ransac;
  double angular_window_deg = 3.0;
  std::string json;
};

struct Candidate {
  Submap map;
  std::string dataset;
  std::int64_t index = 0;  // position within its dataset
  bool same_world = false; // same dataset as the query: world frames agree
};

struct Ranked {
  const Candidate* candidate = nullptr;
  DmmResult result;
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

std::vector<Candidate> load_candidates(const io::MapDatabase& db, const MatchOptions& o, const io::MapLocation& q) {
  std::vector<Candidate> out;
  bool found = o.dataset.empty();
  for (const io::DatasetInfo& d : db.datasets()) {
    if (d.spec.kind != io::DatasetKind::kSubmaps || (!o.dataset.empty() && d.spec.name != o.dataset)) continue;
    found = true;
    Submaps maps = db.load_submaps(d.id);
    for (std::size_t i = 0; i < maps.size(); ++i) {
      if (maps[i].id == o.query && !o.include_self) continue;
      out.push_back({std::move(maps[i]), d.spec.name, static_cast<std::int64_t>(i), d.id == q.dataset_id});
    }
  }
  if (!found) throw InputError("match: no submap dataset named '" + o.dataset + "' in " + o.file);
  return out;
}

// Scores every candidate (or, for dmm with top > 0, at least the top ones exactly); returns the exact
// results, best first (ties: lower map id), and the matching time per map pair.
std::vector<Ranked> rank(const MethodSpec& method, const Submap& query, const std::vector<Candidate>& candidates,
                         const MatchOptions& o, double& ms_per_pair, double& ms_prepare) {
  std::vector<DmmResult> results(candidates.size());
  auto t0 = std::chrono::steady_clock::now();
  if (method.scheme == SchemeKind::kDmmRansac) {
    std::vector<PreparedRansacMap> maps;
    for (const Candidate& c : candidates) maps.push_back(prepare_ransac_map(c.map.points, o.ransac));
    ms_prepare = elapsed_ms(t0);
    t0 = std::chrono::steady_clock::now();
    for (std::size_t m = 0; m < maps.size(); ++m) results[m] = match_dmm_ransac(query.points, maps[m], o.ransac);
  } else {
    std::vector<PreparedMap> maps;
    for (const Candidate& c : candidates) maps.push_back(prepare_map(c.map.points, o.dmm));
    const PreparedQuery q = prepare_query(query.points, o.dmm);
    ms_prepare = elapsed_ms(t0);
    t0 = std::chrono::steady_clock::now();
    if (method.scheme == SchemeKind::kDmmExhaustive) {
      for (std::size_t m = 0; m < maps.size(); ++m) results[m] = match_exhaustive(q, maps[m], o.dmm);
    } else {
      results = match_dmm_many(q, maps, o.dmm, o.top, o.threads);
    }
  }
  ms_per_pair = candidates.empty() ? 0.0 : elapsed_ms(t0) / static_cast<double>(candidates.size());
  ms_prepare = candidates.empty() ? 0.0 : ms_prepare / static_cast<double>(candidates.size());
  std::vector<Ranked> ranked;
  for (std::size_t m = 0; m < candidates.size(); ++m) {
    if (results[m].exact) ranked.push_back({&candidates[m], results[m]});
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) {
    if (a.result.inliers != b.result.inliers) return a.result.inliers > b.result.inliers;
    return a.candidate->map.id < b.candidate->map.id;
  });
  if (o.top > 0 && ranked.size() > static_cast<std::size_t>(o.top)) ranked.resize(static_cast<std::size_t>(o.top));
  return ranked;
}

void run_match(MatchOptions o) {
  if (o.top < 0) throw InputError("--top must be >= 0 (0: every map), got " + std::to_string(o.top));
  if (o.threads < 1) throw InputError("--threads must be >= 1, got " + std::to_string(o.threads));
  o.dmm.angular_window = o.angular_window_deg * std::numbers::pi / 180;
  o.ransac.angular_window = o.dmm.angular_window;
  o.ransac.canonical = o.dmm.canonical;
  o.ransac.inlier_distance = o.dmm.dilation * o.dmm.resolution;  // the same P_Y as dmm
  validate(o.dmm);
  validate(o.ransac);
  const MethodSpec method = parse_method_spec(o.method);
  if (method.scheme != SchemeKind::kDmm && method.scheme != SchemeKind::kDmmRansac &&
      method.scheme != SchemeKind::kDmmExhaustive) {
    throw InputError("match: --method '" + o.method +
                     "' needs map descriptors; match supports dmm, dmm-ransac and dmm-exhaustive (see 'partslam eval')");
  }
  const io::MapDatabase db = io::MapDatabase::open(o.file, io::MapDatabase::Mode::kReadOnly);
  const io::MapLocation where = db.locate(o.query);
  const Submap query = db.load_submap(o.query);
  const std::vector<Candidate> candidates = load_candidates(db, o, where);
  double ms_per_pair = 0, ms_prepare = 0;
  const std::vector<Ranked> ranked = rank(method, query, candidates, o, ms_per_pair, ms_prepare);

  std::printf("query: map %lld (dataset '%s', submap %lld), %zu points\n", static_cast<long long>(o.query),
              where.dataset_name.c_str(), static_cast<long long>(where.index), query.points.size());
  std::printf("method: %s, %zu maps, %.3f ms per map pair (+ %.3f ms preparation per map)\n",
              method.label().c_str(), candidates.size(), ms_per_pair, ms_prepare);
  std::printf("%4s %8s %-16s %6s %7s %8s %8s %8s %10s %10s\n", "rank", "map_id", "dataset", "index", "inliers",
              "fraction", "x[m]", "y[m]", "theta[deg]", "d_world[m]");
  nlohmann::json results = nlohmann::json::array();
  for (std::size_t r = 0; r < ranked.size(); ++r) {
    const Candidate& c = *ranked[r].candidate;
    const DmmResult& m = ranked[r].result;
    const double d_world = (c.map.T_world_map.translation() - query.T_world_map.translation()).norm();
    char world[32] = "-";
    if (c.same_world) std::snprintf(world, sizeof world, "%.2f", d_world);
    std::printf("%4zu %8lld %-16s %6lld %7d %8.3f %8.2f %8.2f %10.2f %10s\n", r + 1,
                static_cast<long long>(c.map.id), c.dataset.c_str(), static_cast<long long>(c.index), m.inliers,
                m.inlier_fraction, m.T_map_query.x, m.T_map_query.y, m.T_map_query.theta * 180 / std::numbers::pi,
                world);
    nlohmann::json j = {{"rank", r + 1},
                        {"map_id", c.map.id},
                        {"dataset", c.dataset},
                        {"index", c.index},
                        {"inliers", m.inliers},
                        {"inlier_fraction", m.inlier_fraction},
                        {"T_map_query", {{"x", m.T_map_query.x}, {"y", m.T_map_query.y}, {"theta", m.T_map_query.theta}}}};
    if (c.same_world) j["world_distance"] = d_world;
    results.push_back(j);
  }
  if (!o.json.empty()) {
    const nlohmann::json j = {{"database", o.file},
                              {"query", {{"map_id", o.query}, {"dataset", where.dataset_name}, {"index", where.index},
                                         {"points", query.points.size()}}},
                              {"method", method.spec},
                              {"maps", candidates.size()},
                              {"ms_per_pair", ms_per_pair},
                              {"ms_prepare_per_map", ms_prepare},
                              {"results", results}};
    io::write_atomically(o.json, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
    std::printf("wrote %s\n", o.json.c_str());
  }
}

}  // namespace

void register_match(CLI::App& app) {
  auto o = std::make_shared<MatchOptions>();
  CLI::App* cmd = app.add_subcommand("match", "Rank stored submaps against one of them by direct map matching");
  cmd->add_option("file", o->file, "map database file")->required();
  cmd->add_option("--query", o->query, "global map id of the query submap (see 'partslam info')")->required();
  cmd->add_option("--method", o->method, "dmm (exact branch-and-bound), dmm-ransac (the paper's baseline) or "
                                         "dmm-exhaustive")->capture_default_str();
  cmd->add_option("--top", o->top, "maps to list; dmm prunes maps that cannot enter them (0: rank all)")
      ->capture_default_str();
  cmd->add_option("--dataset", o->dataset, "only this dataset's submaps (default: every submap dataset)");
  cmd->add_flag("--include-self", o->include_self, "keep the query map itself in the database");
  cmd->add_option("--threads", o->threads, "threads over maps for dmm --top 0 (results do not depend on it)")
      ->capture_default_str();
  cmd->add_option("--window", o->dmm.linear_window,
                  "translation window |x|, |y| <= this [m] (<= 0: whole map)")->capture_default_str();
  cmd->add_option("--angular-window", o->angular_window_deg,
                  "rotation residual about each multiple of 90 deg [deg]")->capture_default_str();
  cmd->add_option("--dilation", o->dmm.dilation, "occupied cells grown by this many cells")->capture_default_str();
  cmd->add_flag("--full-circle", [o](std::int64_t) { o->dmm.canonical = false; },
                "search every rotation (maps not in the canonical frame)");
  cmd->add_option("--ransac-iterations", o->ransac.iterations, "dmm-ransac hypotheses")->capture_default_str();
  cmd->add_option("--seed", o->ransac.seed, "dmm-ransac seed")->capture_default_str();
  cmd->add_option("--json", o->json, "also write the ranking as JSON");
  cmd->callback([o] { run_match(*o); });
}

}  // namespace partslam::apps
