#include "core/ranking/grid_ranker.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "core/error.h"
#include "core/matching/grid_cascade.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

void expect_equal(const std::vector<GridMatch>& index, const std::vector<GridMatch>& scan,
                  const std::string& what) {
  ASSERT_EQ(index.size(), scan.size()) << what;
  for (std::size_t r = 0; r < scan.size(); ++r) {
    EXPECT_EQ(index[r].index, scan[r].index) << what << " rank " << r;
    EXPECT_EQ(index[r].score, scan[r].score) << what << " rank " << r;  // bit for bit
  }
}

// Real query grids (the simulator's submaps, the succinct configuration and its hubness values as the ranker
// computes them) against the other submaps: the ranker's scores, their top k, and the cascade's top k (its
// short lists cover this database) agree.
TEST(GridRanker, TopKThroughTheCascadeEqualsTheScan) {
  const Submaps& maps = testing::simulated_maps();
  const std::vector<MapView> views = testing::point_views(maps);
  const GridConfig config = succinct_grid_config();
  std::vector<GridBits> grids;
  for (const Submap& m : maps) grids.push_back(make_grid(m.points, config));
  const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec("succinct"), RankingConfig{});
  ranker->prepare(views, 1);
  GridConfig indexed = config;
  indexed.index_min_maps = 0;  // the exact index even for this small database
  const std::unique_ptr<Ranker> indexed_ranker = make_grid_ranker(indexed);
  indexed_ranker->prepare(views, 1);
  GridConfig approximate = config;
  approximate.cascade_min_maps = 0;  // the cascade's stages, which this database is too small to prune
  const std::unique_ptr<Ranker> cascade_ranker = make_grid_ranker(approximate);
  cascade_ranker->prepare(views, 1);
  std::vector<std::size_t> everyone(maps.size());
  for (std::size_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  std::vector<const Points2*> points;
  for (const Submap& m : maps) points.push_back(&m.points);
  const std::vector<double> mu = grid_hubness(points, grids, config);
  const GridCascade index(grids, mu, config);
  for (std::size_t qi = 0; qi < maps.size(); qi += 9) {
    const std::vector<GridBits> q = make_query_grids(maps[qi].points, config);
    const std::vector<GridMatch> top = index.top_k(q, 10);
    expect_equal(top, scan_top_k(q, grids, mu, 1.0, 10), "query " + std::to_string(qi));
    const Ranking r = ranker->rank(views[qi], everyone);
    const std::vector<std::size_t> order = ranking_order(r.scores);
    for (std::size_t j = 0; j < top.size(); ++j) {
      EXPECT_EQ(top[j].index, order[j]) << "query " << qi << " rank " << j;
      EXPECT_EQ(top[j].score, r.scores[order[j]]) << "query " << qi << " rank " << j;
    }
    // The ranker asked for its top k (as `partslam match --top` does) answers through the cascade: the same k
    // first, everything else below them.
    for (const Ranker* indexed_one : {indexed_ranker.get(), cascade_ranker.get()}) {
      const Ranking fast = indexed_one->rank(views[qi], everyone, {.num_threads = 1, .top_k = 10});
      const std::vector<std::size_t> fast_order = ranking_order(fast.scores);
      for (std::size_t j = 0; j < top.size(); ++j) {
        EXPECT_EQ(fast_order[j], order[j]) << "query " << qi << " rank " << j;
        EXPECT_EQ(fast.scores[fast_order[j]], r.scores[order[j]]) << "query " << qi << " rank " << j;
      }
      EXPECT_EQ(fast.scores[fast_order[top.size()]], -std::numeric_limits<double>::infinity());
    }
    // The first stored maps as candidates (loops: a log's maps before the query's) go through the index too.
    const std::vector<std::size_t> prefix(everyone.begin(),
                                          everyone.begin() + static_cast<std::ptrdiff_t>(qi / 2 + 11));
    const std::vector<std::size_t> prefix_order = ranking_order(ranker->rank(views[qi], prefix).scores);
    for (const Ranker* indexed_one : {indexed_ranker.get(), cascade_ranker.get()}) {
      const Ranking fast = indexed_one->rank(views[qi], prefix, {.num_threads = 1, .top_k = 5});
      ASSERT_EQ(fast.scores.size(), prefix.size());
      const std::vector<std::size_t> fast_order = ranking_order(fast.scores);
      for (std::size_t j = 0; j < 5; ++j)
        EXPECT_EQ(fast_order[j], prefix_order[j]) << "query " << qi << " rank " << j;
      EXPECT_EQ(fast.scores[fast_order[5]], -std::numeric_limits<double>::infinity());
    }
  }
}

TEST(GridRanker, SpecsNormaliseAndBadOnesAreNamed) {
  EXPECT_EQ(parse_method_spec("grid").spec, "grid:11");
  EXPECT_EQ(parse_method_spec("grid:11").label, "grid 11x11");
  EXPECT_EQ(parse_method_spec("grid:11:hub=100:box=80:shift=3:sub=2").spec,
            "grid:11:box=80:shift=3:sub=2:hub=100");
  EXPECT_FALSE(parse_method_spec("succinct").traits.needs_points);
  EXPECT_FALSE(parse_method_spec("succinct").traits.needs_parts);
  for (const char* bad :
       {"grid:12", "grid:0", "grid:11:shift", "grid:11:foo=1", "grid:11:sub=0", "succinct:3"}) {
    try {
      parse_method_spec(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

TEST(GridRanker, SpecsDeclareWhetherTheyCanBeSharded) {
  // The hubness term learns from every stored map: a ranking split between processes would differ.
  const MethodSpec plain = parse_method_spec("grid:7");
  EXPECT_EQ(plain.label, "grid 7x7");
  EXPECT_TRUE(plain.traits.shardable);
  EXPECT_EQ(plain.traits.stage_score, "grid score");
  const MethodSpec hub = parse_method_spec("grid:7:hub=50");
  EXPECT_EQ(hub.spec, "grid:7:hub=50");
  EXPECT_FALSE(hub.traits.shardable);
  EXPECT_FALSE(parse_method_spec("succinct").traits.shardable);
  for (const MethodSpec& m : {plain, hub}) {
    EXPECT_FALSE(m.traits.needs_points);
    EXPECT_FALSE(m.traits.gives_pose);
  }
}

TEST(GridRanker, SuccinctRanksTheQueryItselfFirstAndThreadsDoNotChangeScores) {
  const Submaps& maps = testing::simulated_maps();
  std::vector<MapView> views;
  for (const Submap& m : maps) views.push_back({&m.points, nullptr});
  const std::unique_ptr<Ranker> one = make_ranker(parse_method_spec("succinct"), {});
  const std::unique_ptr<Ranker> two = make_ranker(parse_method_spec("succinct"), {});
  one->prepare(views, 1);
  two->prepare(views, 2);
  EXPECT_EQ(one->bits_per_map(), 128.0);
  const std::vector<std::size_t> candidates = {30, 5, 12, 0, 44, 61};
  const Ranking r1 = one->rank(views[12], candidates, {1, 0});
  const Ranking r2 = two->rank(views[12], candidates, {2, 0});
  EXPECT_EQ(r1.scores, r2.scores);
  EXPECT_EQ(ranking_order(r1.scores).front(), 2u);
  EXPECT_TRUE(r1.direct.empty());
}

TEST(GridRanker, HubnessSubtractsTheOtherMapsMeanSimilarityToEachStoredMap) {
  const Submaps& maps = testing::simulated_maps();
  std::vector<MapView> views;
  for (std::size_t i = 0; i < 12; ++i) views.push_back({&maps[i * 5].points, nullptr});
  const std::unique_ptr<Ranker> plain = make_ranker(parse_method_spec("grid:11:box=80"), {});
  const std::unique_ptr<Ranker> hub = make_ranker(parse_method_spec("grid:11:box=80:hub=50"), {});
  plain->prepare(views, 1);
  hub->prepare(views, 2);
  const std::vector<std::size_t> candidates = {0, 3, 7, 11};
  const Ranking p = plain->rank(views[5], candidates);
  const Ranking h = hub->rank(views[5], candidates);
  GridConfig c;
  c.box_size = 8.0;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    const std::size_t m = candidates[j];
    // mu_m: the mean similarity of the 11 other maps' queries to map m's grid, on 7 bits.
    const GridBits stored = make_grid(*views[m].points, c);
    double sum = 0;
    for (std::size_t o = 0; o < views.size(); ++o)
      if (o != m) sum += grid_similarity(make_query_grids(*views[o].points, c), stored);
    const double mu = std::round(sum / 11.0 * 127) / 127;
    EXPECT_GT(mu, 0.0);
    EXPECT_NEAR(p.scores[j] - h.scores[j], 0.5 * mu, 1e-12) << "map " << m;
  }
  EXPECT_EQ(hub->bits_per_map(), 128.0);
  EXPECT_EQ(plain->bits_per_map(), 121.0);
}

}  // namespace
}  // namespace partslam
