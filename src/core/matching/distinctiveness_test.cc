#include "core/matching/distinctiveness.h"

#include <gtest/gtest.h>

#include <vector>

namespace partslam {
namespace {

TEST(Distinctiveness, MarginOverTheBestAnswerInAnotherPlace) {
  const std::vector<double> scores = {0.9, 0.8, 0.5, 0.3};
  // Candidate 1 is the same place as 0 (not counted), 2 and 3 are elsewhere.
  const auto elsewhere = [](std::size_t j) { return j >= 2; };
  EXPECT_DOUBLE_EQ(distinctiveness(scores, 0, elsewhere), 0.9 - 0.5);
  EXPECT_DOUBLE_EQ(distinctiveness(scores, 0, [](std::size_t) { return false; }), 0.9);
  EXPECT_DOUBLE_EQ(distinctiveness(scores, 3, [](std::size_t) { return true; }), 0.3 - 0.9);
}

TEST(Distinctiveness, DecisionProbabilityDiscountsTheBestOtherPlace) {
  const std::vector<double> p = {0.9, 0.8, 0.5, 0.3};
  const auto elsewhere = [](std::size_t j) { return j >= 2; };
  EXPECT_DOUBLE_EQ(decision_probability(p, 0, elsewhere), 0.9 * (1 - 0.5));
  EXPECT_DOUBLE_EQ(decision_probability(p, 0, [](std::size_t) { return false; }), 0.9);
  // A look-alike as probable as the answer leaves little confidence; a sure other place leaves none.
  EXPECT_DOUBLE_EQ(decision_probability(std::vector<double>{0.7, 0.7}, 0, [](std::size_t) { return true; }),
                   0.7 * 0.3);
  EXPECT_DOUBLE_EQ(decision_probability(std::vector<double>{0.7, 1.0}, 0, [](std::size_t) { return true; }), 0.0);
  // Within [0, 1] and never above the answer's own probability.
  for (double a : {0.0, 0.2, 1.0})
    for (double b : {0.0, 0.6, 1.0}) {
      const double d = decision_probability(std::vector<double>{a, b}, 0, [](std::size_t) { return true; });
      EXPECT_GE(d, 0.0);
      EXPECT_LE(d, a);
    }
}

}  // namespace
}  // namespace partslam
