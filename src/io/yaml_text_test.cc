#include "io/yaml_text.h"

#include <gtest/gtest.h>

namespace partslam::io {
namespace {

TEST(YamlText, QuotesAndEscapesWhatAPlainScalarCannotHold) {
  EXPECT_EQ(yaml_double_quoted("map.pgm"), "\"map.pgm\"");
  EXPECT_EQ(yaml_double_quoted(""), "\"\"");
  EXPECT_EQ(yaml_double_quoted("m: 2 #1"), "\"m: 2 #1\"");
  EXPECT_EQ(yaml_double_quoted("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(yaml_double_quoted(std::string_view("a\nb\t\r\x7f\0z", 8)), "\"a\\x0ab\\x09\\x0d\\x7f\\x00z\"");
  EXPECT_EQ(yaml_double_quoted("k\xc3\xa4rta"), "\"k\xc3\xa4rta\"");  // UTF-8 as it is
}

}  // namespace
}  // namespace partslam::io
