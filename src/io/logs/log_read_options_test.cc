#include "io/logs/log_read_options.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

TEST(LogReadOptions, TheDefaultsAreValid) { EXPECT_NO_THROW(validate(LogReadOptions{})); }

TEST(LogReadOptions, EachBadFieldIsNamed) {
  LogReadOptions o;
  o.max_points = 0;
  EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("max_points")));
  o = {};
  o.max_scan_jump = 0.0;
  EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("max_scan_jump")));
  o = {};
  o.max_scan_jump = std::nan("");
  EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("max_scan_jump")));
  o = {};
  o.min_range = 80.5;  // above max_usable_range
  EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("max_usable_range")));
  for (double share : {-0.1, 1.5, std::nan("")}) {
    o = {};
    o.no_return_code_share = share;
    EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("no_return_code_share")));
  }
  for (double range : {-1.0, static_cast<double>(INFINITY), std::nan("")}) {
    o = {};
    o.no_return_code_min_range = range;
    EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("no_return_code_min_range")));
  }
  o = {};
  o.flaser_spacing = static_cast<FlaserSpacing>(7);
  EXPECT_THAT([&] { validate(o); }, ThrowsMessage<InputError>(HasSubstr("flaser_spacing")));
}

}  // namespace
}  // namespace partslam::io
