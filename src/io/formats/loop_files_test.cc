#include "io/formats/loop_files.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

namespace partslam::io {
namespace {

Submaps three_maps() {
  Submaps maps(3);
  for (std::size_t i = 0; i < maps.size(); ++i) {
    maps[i].id = static_cast<std::int64_t>(10 + i);
    maps[i].T_world_map = Pose2{2.0 * static_cast<double>(i), 1.0, 0.5 * static_cast<double>(i)};
  }
  return maps;
}

TEST(LoopFiles, G2oHasAVertexPerMapAnEdgePerStepAndOnePerClosure) {
  const Submaps maps = three_maps();
  std::vector<LoopClosure> accepted(1);
  accepted[0].query = 2;
  accepted[0].match = 0;
  accepted[0].T_match_query = Pose2{0.25, -0.5, 0.125};
  std::ostringstream out;
  write_g2o(out, maps, accepted);
  std::istringstream in(out.str());
  std::string tag;
  int vertices = 0, edges = 0;
  std::string last;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    fields >> tag;
    vertices += tag == "VERTEX_SE2";
    edges += tag == "EDGE_SE2";
    last = line;
  }
  EXPECT_EQ(vertices, 3);
  EXPECT_EQ(edges, 3);  // 10-11, 11-12 and the closure 10-12
  EXPECT_EQ(last, "EDGE_SE2 10 12 0.25 -0.5 0.125 25 0 0 25 0 100");
  EXPECT_NE(out.str().find("VERTEX_SE2 11 2 1 0.5\n"), std::string::npos) << out.str();
}

TEST(LoopFiles, JsonNamesTheMapsAndWhetherEachClosureIsAccepted) {
  const Submaps maps = three_maps();
  std::vector<LoopClosure> closures(2);
  closures[0].query = 2, closures[0].match = 0, closures[0].confidence = 0.5;
  closures[1].query = 2, closures[1].match = 1, closures[1].confidence = 0.1;
  closures[1].in_group = false;
  const nlohmann::json j = closures_json(maps, closures, 0.2);
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["query"], 12);
  EXPECT_EQ(j[0]["match"], 10);
  EXPECT_TRUE(j[0]["accepted"]);
  EXPECT_FALSE(j[1]["accepted"]);
  EXPECT_TRUE(j[0]["consistent_group"]);
  EXPECT_FALSE(j[1]["consistent_group"]);
  EXPECT_TRUE(j[1]["graph_agrees"]);
  LoopEvaluation e;
  e.relevant_pairs = 7;
  e.curve.push_back({0.3, 1.0, 0.25});
  const nlohmann::json ej = loop_evaluation_json(e);
  EXPECT_EQ(ej["relevant_pairs"], 7);
  EXPECT_EQ(ej["curve"][0]["recall"], 0.25);
}

}  // namespace
}  // namespace partslam::io
