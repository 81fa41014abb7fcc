// Python bindings of core/matching: dMM (prepare a query and maps once, match one or many, with the relative
// pose T_map_query), method specs, and ranking through the library's one entry point, make_ranker: a Ranker
// bound to a spec (prepare the stored maps once, rank queries against them) and rank(), both at once. Every
// matching and ranking call releases the GIL.
#include "casters.h"
// (casters.h first: see its header comment)
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>

#include "bindings.h"
#include "core/error.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_ransac.h"
#include "core/matching/verification.h"
#include "core/ranking/method_spec.h"
#include "core/ranking/ranking.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

// A ranker made by make_ranker for one method spec, with the stored maps it was prepared with (its MapViews
// point into them). prepare() and rank() may run on several Python threads at once (the GIL is released):
// rank() is const and thread-safe in the library, prepare() excludes it.
class BoundRanker {
 public:
  BoundRanker(const std::string& method, const RankingConfig& config)
      : spec_(parse_method_spec(method)), ranker_(make_ranker(spec_, config)) {}

  const MethodSpec& spec() const { return spec_; }
  double bits_per_map() const {
    std::shared_lock lock(mutex_);
    return ranker_->bits_per_map();
  }
  std::size_t size() const {
    std::shared_lock lock(mutex_);
    return size_;
  }

  void prepare(std::optional<std::vector<Points2>> points,
               std::optional<std::vector<std::vector<Part>>> parts, int threads,
               std::optional<std::vector<Points2>> origins) {
    std::unique_lock lock(mutex_);
    if (!points && !parts) throw InputError("prepare: give the stored maps' points, parts, or both");
    if (points && parts && points->size() != parts->size()) {
      throw InputError("prepare: " + std::to_string(points->size()) + " point sets but " +
                       std::to_string(parts->size()) + " part lists");
    }
    if (origins && (!points || origins->size() != points->size())) {
      throw InputError("prepare: " + std::to_string(origins->size()) + " origin sets but " +
                       std::to_string(points ? points->size() : 0) +
                       " point sets (the laser origins belong to the stored maps' points, one set each)");
    }
    points_ = std::move(points);
    parts_ = std::move(parts);
    origins_ = std::move(origins);
    const std::size_t n = points_ ? points_->size() : parts_->size();
    std::vector<MapView> views(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (points_) views[i].points = &(*points_)[i];
      if (parts_) views[i].parts = &(*parts_)[i];
      if (origins_) views[i].origins = &(*origins_)[i];
    }
    size_ = 0;
    ranker_->prepare(views, threads);
    size_ = n;
  }

  Ranking rank(const std::optional<Points2>& query_points,
               const std::optional<std::vector<Part>>& query_parts,
               std::optional<std::vector<std::size_t>> candidates, int threads, int top_k,
               const std::optional<Points2>& query_origins) const {
    std::shared_lock lock(mutex_);
    // Without stored maps there is no ranking: an empty result would read as "nothing matched".
    if (size_ == 0) {
      throw InputError("rank: no stored maps to rank (prepare() was not called, or was given none: map_points is "
                       "empty)");
    }
    if (!candidates) {
      candidates.emplace(size_);
      for (std::size_t i = 0; i < size_; ++i) (*candidates)[i] = i;
    }
    for (const std::size_t c : *candidates) {
      if (c >= size_) {
        throw InputError("rank: candidate " + std::to_string(c) + " is not a prepared map (" +
                         std::to_string(size_) + " prepared)");
      }
    }
    if (query_origins && !query_points) throw InputError("rank: query_origins given without query_points");
    const MapView query{query_points ? &*query_points : nullptr, query_parts ? &*query_parts : nullptr,
                        query_origins ? &*query_origins : nullptr};
    return ranker_->rank(query, *candidates, RankOptions{threads, top_k});
  }

 private:
  MethodSpec spec_;
  std::unique_ptr<Ranker> ranker_;
  std::optional<std::vector<Points2>> points_;
  std::optional<std::vector<std::vector<Part>>> parts_;
  std::optional<std::vector<Points2>> origins_;
  std::size_t size_ = 0;
  mutable std::shared_mutex mutex_;
};

void define_dmm(py::module_& m) {
  py::class_<DmmConfig> config(m, "DmmConfig", "The dMM search window and grid (core/matching/dmm.h)");
  def_config_fields(config);
  config
      .def_readwrite("extra_directions", &DmmConfig::extra_directions,
                     "canonical: further families turned by these offsets (a building's wings) [rad]")
      .def("validate", py::overload_cast<const DmmConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(config);
  m.def(
      "dmm_config_for_dictionary", &dmm_config_for_dictionary,
      "DmmConfig for matching small crops against a whole dictionary map (the whole target as the window).");

  py::class_<PreparedQuery>(m, "PreparedQuery",
                            "A dMM query prepared once (its rotations), matched against many maps")
      .def_readonly("config", &PreparedQuery::config)
      .def_readonly("num_points", &PreparedQuery::num_points)
      .def_readonly("angular_step", &PreparedQuery::angular_step, "rotation step used [rad]")
      .def_property_readonly("num_rotations", [](const PreparedQuery& q) { return q.rotations.size(); });
  py::class_<PreparedMap>(m, "PreparedMap", "A dMM target map prepared once (occupancy grid and pyramid)")
      .def_readonly("config", &PreparedMap::config)
      .def_readonly("num_points", &PreparedMap::num_points);

  py::class_<DmmResult>(m, "DmmResult", "The exact Eq. 1 maximum and the pose that reaches it")
      .def_readonly("inliers", &DmmResult::inliers,
                    "query points on occupied cells of the map at T_map_query")
      .def_readonly("inlier_fraction", &DmmResult::inlier_fraction, "inliers / query points")
      .def_readonly("T_map_query", &DmmResult::T_map_query,
                    "(x, y, theta): maps query points into the map frame")
      .def_readonly("exact", &DmmResult::exact, "false when top-k pruning dropped the map (inliers then 0)")
      .def_readonly("candidates_scored", &DmmResult::candidates_scored)
      .def("__repr__", [](const DmmResult& r) {
        return "<partslam.DmmResult inliers=" + std::to_string(r.inliers) +
               " fraction=" + std::to_string(r.inlier_fraction) + " T_map_query=(" +
               std::to_string(r.T_map_query.x) + ", " + std::to_string(r.T_map_query.y) + ", " +
               std::to_string(r.T_map_query.theta) + ")>";
      });

  m.def("prepare_query", &prepare_query, "points"_a, "config"_a = DmmConfig{}, release_gil(),
        "Prepares a dMM query (points in its own frame, e.g. a submap's).");
  m.def("prepare_map", &prepare_map, "points"_a, "config"_a = DmmConfig{}, release_gil(),
        "Prepares a dMM target map.");
  m.def("match_dmm", &match_dmm, "query"_a, "map"_a, release_gil(),
        "Exact maximum of Eq. 1 by branch-and-bound, with T_map_query; the settings are those both were "
        "prepared "
        "with.");
  m.def(
      "match_dmm",
      [](const Points2& query, const Points2& map, const DmmConfig& config) {
        // No points on either side leaves nothing to match: 0 inliers would read as "not the same place".
        if (query.empty()) throw InputError("match_dmm: query_points is empty (shape (0, 2)): nothing to match");
        if (map.empty()) throw InputError("match_dmm: map_points is empty (shape (0, 2)): nothing to match against");
        return match_dmm(prepare_query(query, config), prepare_map(map, config));
      },
      "query_points"_a, "map_points"_a, "config"_a = DmmConfig{}, release_gil(),
      "Prepares both point sets with config and matches them; raises InputError when either is empty.");
  m.def("match_exhaustive", &match_exhaustive, "query"_a, "map"_a, release_gil(),
        "The same maximum by scoring every candidate (the reference).");
  m.def(
      "match_dmm_many",
      [](const PreparedQuery& query, const std::vector<const PreparedMap*>& maps, int top_k, int threads) {
        return match_dmm_many(query, std::span<const PreparedMap* const>(maps), top_k, threads);
      },
      "query"_a, "maps"_a, "top_k"_a = 0, "threads"_a = 1, release_gil(),
      "1-to-N: one DmmResult per map. top_k > 0 drops maps that provably cannot enter the top k (exact "
      "False).");
}

void define_method_specs(py::module_& m) {
  py::class_<MethodSpec>(m, "MethodSpec", "A parsed method spec (core/ranking/method_spec.h)")
      .def_readonly("name", &MethodSpec::name)
      .def_readonly("spec", &MethodSpec::spec, "the normalised text")
      .def_readonly("label", &MethodSpec::label, "the paper's name")
      .def_property_readonly(
          "parts", [](const MethodSpec& s) { return s.traits.parts; }, "K: parts per stored map it reads")
      .def_property_readonly(
          "needs_points", [](const MethodSpec& s) { return s.traits.needs_points; },
          "the stored form is built from the points")
      .def_property_readonly(
          "needs_parts", [](const MethodSpec& s) { return s.traits.needs_parts; }, "needs every map's CPD parts")
      .def_property_readonly(
          "gives_pose", [](const MethodSpec& s) { return s.traits.gives_pose; }, "returns T_map_query")
      .def_property_readonly(
          "shardable", [](const MethodSpec& s) { return s.traits.shardable; },
          "a stored map's score depends on it and the query alone")
      .def("__repr__", [](const MethodSpec& s) { return "<partslam.MethodSpec " + s.spec + ">"; });
  m.def("parse_method_spec", &parse_method_spec, "text"_a,
        "Parses a spec such as 'dmm', 'rerank:20', 'hmm:3'.");
  m.def(
      "methods",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const MethodEntry& e : method_registry()) out.emplace_back(e.name, e.syntax);
        return out;
      },
      "Every registered method as (name, syntax).");
}

void define_ranking(py::module_& m) {
  py::class_<DmmRansacConfig> ransac(m, "DmmRansacConfig",
                                     "dMM-RANSAC settings (core/matching/dmm_ransac.h)");
  ransac.def_readwrite("iterations", &DmmRansacConfig::iterations)
      .def_readwrite("inlier_distance", &DmmRansacConfig::inlier_distance, "[m]")
      .def_readwrite("resolution", &DmmRansacConfig::resolution, "[m]")
      .def_readwrite("min_sample_distance", &DmmRansacConfig::min_sample_distance, "[m]")
      .def_readwrite("length_tolerance", &DmmRansacConfig::length_tolerance, "[m]")
      .def_readwrite("canonical", &DmmRansacConfig::canonical)
      .def_readwrite("angular_window", &DmmRansacConfig::angular_window, "[rad]")
      .def_readwrite("max_draws", &DmmRansacConfig::max_draws)
      .def_readwrite("seed", &DmmRansacConfig::seed);
  def_keyword_init(ransac);

  py::class_<PartsConfig> parts_config(m, "PartsConfig",
                                       "How the part methods read parts (core/parts/descriptor_database.h)");
  parts_config
      .def_readwrite(
          "codec", &PartsConfig::codec,
          "CodecConfig or None: stored parts go through it (what a database holds); assign a new one")
      .def_readwrite("hmm_query_parts", &PartsConfig::hmm_query_parts)
      .def_readwrite("origin_gate", &PartsConfig::origin_gate, "descriptor matcher's origin gate [m]; 0 = the paper")
      .def("validate", py::overload_cast<const PartsConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(parts_config);

  py::class_<RankingConfig> config(m, "RankingConfig",
                                   "Settings every ranker reads (core/ranking/ranking.h)");
  config.def_readwrite("dmm", &RankingConfig::dmm)
      .def_readwrite("ransac", &RankingConfig::ransac)
      .def_readwrite("parts", &RankingConfig::parts, "PartsConfig: iMM, hMM and their rerank")
      .def_readwrite("bits_per_point", &RankingConfig::bits_per_point)
      .def("validate", py::overload_cast<const RankingConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(config);

  py::class_<Ranking>(m, "Ranking",
                      "Scores of the candidates (higher = more likely the same place), in their order")
      .def_property_readonly("scores", [](const Ranking& r) { return to_array(r.scores); })
      .def_property_readonly(
          "order", [](const Ranking& r) { return ranking_order(r); },
          "candidate positions best first (rerank: its reordered top R first)")
      .def_readonly("tiers", &Ranking::tiers, "rerank: 1 for its top R (scored by dMM), 0 below; else empty")
      .def_readonly("direct", &Ranking::direct,
                    "per candidate, the DmmResult where a direct match ran, else None")
      .def_property_readonly(
          "shortlist_scores", [](const Ranking& r) { return to_array(r.shortlist_scores); },
          "rerank: the first stage's scores; empty otherwise")
      .def_readonly(
          "probability", &Ranking::probability,
          "per candidate where dMM verified its match, the probability that it is the same place at "
          "that pose (calibrated when both maps have laser origins), None where it did not (below "
          "rerank's top R); empty for methods that do not verify (dmm:eq1, descriptors)")
      .def_readonly("runner_up", &Ranking::runner_up,
                    "where verified, the probability of the map's most probable other pose, else None")
      .def_property_readonly(
          "pose_ambiguous",
          [](const Ranking& r) {
            std::vector<std::optional<bool>> out(r.probability.size());
            for (std::size_t i = 0; i < out.size() && i < r.runner_up.size(); ++i)
              out[i] = pose_ambiguous(r.probability[i], r.runner_up[i]);
            return out;
          },
          "where verified, whether another pose of the map is nearly as probable (pose_ambiguous), else None")
      .def_readonly("prep_ms", &Ranking::prep_ms, "the query's own preparation [ms]")
      .def_readonly("match_ms", &Ranking::match_ms, "matching the candidates [ms]");
  m.attr("AMBIGUOUS_POSE_SHARE") = kAmbiguousPoseShare;
  m.def("pose_ambiguous", py::overload_cast<double, double>(&pose_ambiguous), "probability"_a, "runner_up"_a,
        "Whether a verified pose cannot be trusted: the map's most probable other pose reaches "
        "AMBIGUOUS_POSE_SHARE of its probability (a corridor's half turn).");

  py::class_<BoundRanker>(
      m, "Ranker",
      "The ranker of one method spec (make_ranker): prepare the stored maps once, then rank "
      "queries against them.")
      .def(py::init<const std::string&, const RankingConfig&>(), "method"_a, "config"_a = RankingConfig{})
      .def_property_readonly("method", &BoundRanker::spec)
      .def_property_readonly("bits_per_map", &BoundRanker::bits_per_map, "storage per stored map [bits]")
      .def("__len__", &BoundRanker::size, "stored maps prepared")
      .def(
          "prepare", &BoundRanker::prepare, "points"_a = py::none(), "parts"_a = py::none(), "threads"_a = 1,
          "origins"_a = py::none(), release_gil(),
          "Prepares the stored maps: their points (list of (n, 2) arrays) and, for part methods, their parts "
          "(list of lists of Part); origins: their laser origins (Submap.origins, one (k, 2) array per map), "
          "from which dMM's verification casts each map's free space (without them its probability reads "
          "structure only). Candidates of rank() index this list.")
      .def("rank", &BoundRanker::rank, "query_points"_a = py::none(), "query_parts"_a = py::none(),
           "candidates"_a = py::none(), "threads"_a = 1, "top_k"_a = 0, "query_origins"_a = py::none(),
           release_gil(),
           "Scores the candidates (default: every prepared map) for the query; query_origins: its laser "
           "origins, as prepare()'s origins.");

  m.def(
      "rank",
      [](const std::string& method, const Points2& query_points, std::vector<Points2> map_points, int threads,
         const RankingConfig& config, const std::optional<std::vector<Part>>& query_parts,
         std::optional<std::vector<std::vector<Part>>> map_parts, int top_k,
         const std::optional<Points2>& query_origins, std::optional<std::vector<Points2>> map_origins) {
        BoundRanker ranker(method, config);
        ranker.prepare(std::move(map_points), std::move(map_parts), threads, std::move(map_origins));
        return ranker.rank(query_points, query_parts, std::nullopt, threads, top_k, query_origins);
      },
      "method"_a, "query_points"_a, "map_points"_a, "threads"_a = 1, "config"_a = RankingConfig{},
      "query_parts"_a = py::none(), "map_parts"_a = py::none(), "top_k"_a = 0, "query_origins"_a = py::none(),
      "map_origins"_a = py::none(), release_gil(),
      "Ranks the maps for the query with any registered method (make_ranker, prepare, rank); raises "
      "InputError when map_points is empty; query_origins and map_origins: the laser origins, as Ranker's.");
  m.def("ranking_order", py::overload_cast<const std::vector<double>&>(&ranking_order), "scores"_a,
        "Positions sorted by score, best first; ties keep their order.");
}

}  // namespace

void define_matching(py::module_& m) {
  define_dmm(m);
  define_method_specs(m);
  define_ranking(m);
}

}  // namespace partslam::python
