#include "core/matching/method_spec.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace partslam {
namespace {

TEST(MethodSpec, ParsesEverySchemeWithPaperLabels) {
  EXPECT_EQ(parse_method_spec("dmm").label(), "dMM");
  EXPECT_EQ(parse_method_spec("dmm-ransac").label(), "dMM-RANSAC");
  EXPECT_EQ(parse_method_spec("imm:3").label(), "iMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3").label(), "hMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3:maxmax").label(), "Max-Max hMM cpd:3");
  EXPECT_EQ(parse_method_spec("hmm:3:summax").label(), "Sum-Max hMM cpd:3");
  EXPECT_EQ(parse_method_spec("rerank:10:3").label(), "rerank10 hMM cpd:3");
  const MethodSpec r = parse_method_spec("rerank:20:3");
  EXPECT_EQ(r.rerank, 20);
  EXPECT_EQ(r.parts, 3);
  EXPECT_TRUE(r.uses_points());
  EXPECT_FALSE(parse_method_spec("imm:5").uses_points());
}

TEST(MethodSpec, DefaultMatchersFollowThePaper) {
  EXPECT_EQ(parse_method_spec("imm:2").matcher, Matcher::kSumMax);
  EXPECT_EQ(parse_method_spec("hmm:2").matcher, Matcher::kSumMaxWeighted);
  EXPECT_EQ(parse_method_spec("hmm:2").spec, "hmm:2:smw");
}

TEST(MethodSpec, ListAndMaxParts) {
  const auto methods = parse_method_list("dmm,imm:5,hmm:3");
  ASSERT_EQ(methods.size(), 3u);
  EXPECT_EQ(max_parts(methods), 5);
}

TEST(MethodSpec, RerankTakesAnySuccinctFirstStage) {
  const MethodSpec paper = parse_method_spec("rerank:20:3");
  ASSERT_EQ(paper.stages.size(), 1u);
  EXPECT_EQ(paper.stages[0].spec, "hmm:3:smw");
  EXPECT_EQ(paper.spec, "rerank:20:3");
  EXPECT_EQ(paper.label(), "rerank20 hMM cpd:3");
  EXPECT_TRUE(paper.needs_points);
  EXPECT_TRUE(paper.needs_parts);
  const MethodSpec imm = parse_method_spec("rerank:10:imm:2");
  EXPECT_EQ(imm.stages[0].spec, "imm:2:summax");
  EXPECT_EQ(imm.label(), "rerank10 iMM cpd:2");
  EXPECT_EQ(max_parts({imm}), 2);
  EXPECT_FALSE(parse_method_spec("rerank:10").stages.empty());
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
