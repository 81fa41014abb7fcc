#include "core/ranking/method_spec.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace partslam {
namespace {

TEST(MethodSpec, ParsesEverySchemeWithPaperLabels) {
  EXPECT_EQ(parse_method_spec("dmm").label, "dMM");
  EXPECT_EQ(parse_method_spec("dmm-ransac").label, "dMM-RANSAC");
  EXPECT_EQ(parse_method_spec("imm:3").label, "iMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3").label, "hMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3:maxmax").label, "Max-Max hMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3:summax").label, "Sum-Max hMM cpd:3");
  EXPECT_EQ(parse_method_spec("rerank:10:3").label, "rerank10 hMM cpd:3");
  const MethodSpec r = parse_method_spec("rerank:20:3");
  EXPECT_EQ(r.traits.parts, 3);
  EXPECT_TRUE(r.traits.needs_points);
  EXPECT_FALSE(parse_method_spec("imm:5").traits.needs_points);
}

TEST(MethodSpec, DefaultMatchersFollowThePaper) {
  EXPECT_EQ(parse_method_spec("imm:2").spec, "imm:2:summax");
  EXPECT_EQ(parse_method_spec("hmm:2").spec, "hmm:2:smw");
}

TEST(MethodSpec, ListAndMaxParts) {
  const auto methods = parse_method_list("dmm,imm:5,hmm:3");
  ASSERT_EQ(methods.size(), 3u);
  EXPECT_EQ(max_parts(methods), 5);
}

TEST(MethodSpec, RerankTakesAnySuccinctFirstStage) {
  const MethodSpec paper = parse_method_spec("rerank:20:3");
  EXPECT_EQ(paper.spec, "rerank:20:3");
  EXPECT_EQ(paper.label, "rerank20 hMM cpd:3");
  EXPECT_TRUE(paper.traits.needs_points);
  EXPECT_TRUE(paper.traits.needs_parts);
  EXPECT_TRUE(paper.traits.gives_pose);
  EXPECT_FALSE(paper.traits.shardable);
  EXPECT_EQ(paper.traits.query_parts, QueryParts::kList);
  EXPECT_EQ(paper.traits.stage_score, "hMM score");
  EXPECT_EQ(parse_method_spec("rerank:20:hmm:3").spec, "rerank:20:3");
  const MethodSpec imm = parse_method_spec("rerank:10:imm:2");
  EXPECT_EQ(imm.spec, "rerank:10:imm:2:summax");
  EXPECT_EQ(imm.label, "rerank10 iMM cpd:2");
  EXPECT_EQ(imm.traits.query_parts, QueryParts::kDescriptor);
  EXPECT_EQ(max_parts({imm}), 2);
  const MethodSpec succinct = parse_method_spec("rerank:10");
  EXPECT_EQ(succinct.spec, "rerank:10:succinct");
  EXPECT_FALSE(succinct.traits.needs_parts);
  EXPECT_EQ(succinct.traits.stage_score, "succinct score");
}

TEST(MethodSpec, DirectMethodsGivePosesAndShard) {
  for (const char* text : {"dmm", "dmm-ransac", "dmm-exhaustive"}) {
    const MethodSpec m = parse_method_spec(text);
    EXPECT_TRUE(m.traits.gives_pose) << text;
    EXPECT_TRUE(m.traits.needs_points) << text;
    EXPECT_TRUE(m.traits.shardable) << text;
    EXPECT_TRUE(m.traits.stage_score.empty()) << text;
  }
  const MethodSpec imm = parse_method_spec("imm:3");
  EXPECT_FALSE(imm.traits.gives_pose);
  EXPECT_TRUE(imm.traits.shardable);
  EXPECT_EQ(imm.traits.stage_score, "iMM score");
}

TEST(MethodSpec, OptionsAreTheirMethodsOwn) {
  struct Other final : MethodOptions {};
  EXPECT_THROW(parse_method_spec("imm:3").options_as<Other>(), InputError);
}

TEST(MethodSpec, RejectsBadSpecsWithTheSpecInTheMessage) {
  for (const char* bad : {"", "foo", "imm", "imm:0", "imm:x", "hmm:3:best", "rerank:x", "rerank:10:dmm", "rerank:5:rerank:3", "dmm:3", "imm:3:", "imm:101"}) {
    try {
      parse_method_spec(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_method_list("dmm,,imm:3"), InputError);
}

}  // namespace
}  // namespace partslam
