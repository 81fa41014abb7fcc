// The progress bar draws one bar per phase and never goes backwards (no 40 % 309/772 followed by 39 % 308/772).
#include "apps/progress_bar.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace partslam::apps {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

// "done/total" of every redraw, in order.
std::vector<std::string> draws(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while ((at = text.find("% ", at)) != std::string::npos) {
    at += 2;
    const std::size_t end = text.find_first_of("\r\n", at);
    out.push_back(text.substr(at, end == std::string::npos ? std::string::npos : end - at));
  }
  return out;
}

TEST(ProgressBar, LateReportsOfAPhaseAreDropped) {
  std::ostringstream out;
  {
    ProgressBar bar(out, true);
    bar("tasks", 309, 772);
    bar("tasks", 308, 772);  // another thread's item, reported late
    bar("tasks", 310, 772);
    bar("tasks", 40, 772);
    bar("tasks", 772, 772);
  }
  EXPECT_THAT(draws(out.str()), ElementsAre("309/772", "772/772"));
  EXPECT_THAT(out.str(), Not(HasSubstr("308/772")));
}

TEST(ProgressBar, PercentNeverDecreasesWithinAPhase) {
  std::ostringstream out;
  ProgressBar bar(out, true);
  for (std::size_t d : {1, 5, 3, 6, 2, 20, 19, 20}) bar("CPD", d, 20);
  std::vector<int> percents;
  const std::string text = out.str();
  for (std::size_t at = 0; (at = text.find("] ", at)) != std::string::npos; at += 2)
    percents.push_back(std::stoi(text.substr(at + 2, 3)));
  ASSERT_FALSE(percents.empty());
  for (std::size_t i = 1; i < percents.size(); ++i) EXPECT_GE(percents[i], percents[i - 1]) << text;
  EXPECT_EQ(percents.back(), 100);
}

TEST(ProgressBar, ANewStageOrCountOrACompletedPhaseStartsANewBar) {
  std::ostringstream out;
  ProgressBar bar(out, true);
  bar("prepare", 5, 100);
  bar("rank", 1, 100);      // a new stage starts from its own count
  bar("rank", 1, 50);       // a new count: a new phase
  bar("rank", 50, 50);      // completed
  bar("rank", 49, 50);      // late after it completed: dropped
  bar("rank", 1, 50);       // the same stage again, back in the first half after it completed: a new bar
  EXPECT_THAT(draws(out.str()), ElementsAre("5/100", "1/100", "1/50", "50/50", "1/50"));
}

TEST(ProgressBar, DisabledDrawsNothing) {
  std::ostringstream out;
  {
    ProgressBar bar(out, false);
    bar("tasks", 1, 2);
  }
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace partslam::apps
