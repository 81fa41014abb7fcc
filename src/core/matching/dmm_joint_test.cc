#include "core/matching/dmm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "core/maps/occupancy_grid.h"
#include "core/testing/simulated_maps.h"
#include "core/testing/synthetic_maps.h"

namespace partslam {
namespace {

// The joint search returns exactly the k best maps (ties: the earlier map) with match_dmm's scores, on synthetic
// maps and on the simulator's submaps (many near-ties), with less work than scoring every map.
TEST(MatchDmmJoint, EqualsTheExactTopK) {
  const testing::QueryAndMaps data = testing::query_and_sixteen_maps();
  const Points2& query = data.query;
  std::vector<PreparedMap> maps;
  for (const Points2& m : data.maps) maps.push_back(prepare_map(m));
  const auto check = [](const Points2& points, const std::vector<const PreparedMap*>& maps, int k) {
    const PreparedQuery q = prepare_query(points);
    const std::vector<DmmResult> all = match_dmm_many(q, maps);
    std::vector<std::size_t> order(maps.size());
    for (std::size_t m = 0; m < order.size(); ++m) order[m] = m;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return all[a].inliers > all[b].inliers; });
    const std::vector<DmmResult> joint = match_dmm_joint(q, maps, k);
    std::int64_t work_joint = 0, work_all = 0;
    for (std::size_t r = 0; r < order.size(); ++r) {
      const std::size_t m = order[r];
      work_joint += joint[m].candidates_scored, work_all += all[m].candidates_scored;
      EXPECT_EQ(joint[m].exact, r < static_cast<std::size_t>(k)) << "map " << m << " rank " << r << " k " << k;
      if (joint[m].exact) {
        EXPECT_EQ(joint[m].inliers, all[m].inliers) << "map " << m;
        // The reported pose scores what is claimed (up to cell-boundary rounding of t + R x).
        EXPECT_NEAR(count_inliers(points, maps[m]->grid, joint[m].T_map_query), joint[m].inliers,
                    0.02 * joint[m].inliers + 1);
      } else {
        EXPECT_EQ(joint[m].inliers, 0);
      }
    }
    EXPECT_LT(work_joint, work_all);
  };
  std::vector<const PreparedMap*> synthetic;
  for (const PreparedMap& m : maps) synthetic.push_back(&m);
  for (const int k : {1, 3, 5}) check(query, synthetic, k);
  const Submaps& sim = testing::simulated_maps();
  std::vector<PreparedMap> prepared;
  for (std::size_t m = 0; m < 80; ++m) prepared.push_back(prepare_map(sim[m * 3].points));
  std::vector<const PreparedMap*> pointers;
  for (const PreparedMap& m : prepared) pointers.push_back(&m);
  for (const int k : {1, 4}) check(sim[200].points, pointers, k);
  EXPECT_THROW(match_dmm_joint(prepare_query(query), synthetic, 0), InputError);
}

}  // namespace
}  // namespace partslam
