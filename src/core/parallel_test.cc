#include "core/parallel.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace partslam {
namespace {

TEST(ParallelFor, EveryItemOnceForAnyThreads) {
  for (int threads : {1, 2, 4}) {
    std::vector<int> hits(1000, 0);
    parallel_for(hits.size(), threads, [&](std::size_t i) { ++hits[i]; });
    for (int h : hits) ASSERT_EQ(h, 1) << threads << " threads";
  }
}

// A body's exception reaches the caller (it must not leave the OpenMP region, which ends the process, e.g. a
// stored map too wide for dMM during `match`'s preparation): the lowest failing index's, for any thread count.
TEST(ParallelFor, RethrowsTheLowestItemsExceptionAfterTheLoop) {
  for (int threads : {1, 2, 4}) {
    try {
      parallel_for(200, threads, [](std::size_t i) {
        if (i == 37 || i == 120) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "no exception with " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 37") << threads << " threads";
    }
  }
}

}  // namespace
}  // namespace partslam
