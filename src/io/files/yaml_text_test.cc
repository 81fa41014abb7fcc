#include "io/files/yaml_text.h"

#include <gtest/gtest.h>

#include "io/testing/test_files.h"

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

// A PNG or PGM given where YAML is read is told apart from text (the YAML reader printed its bytes).
TEST(YamlText, BinaryFilesAreToldFromText) {
  testing::TempDir dir;
  testing::write_bytes(dir / "map.png", std::string_view("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
  testing::write_bytes(dir / "map.pgm", std::string_view("P5\n4 1\n255\n\0\xff\x01\xfe", 15));
  testing::write_bytes(dir / "map.yaml", "image: \"map.pgm\"\r\nresolution: 0.05\n\torigin: [0, 0, 0]\n");
  EXPECT_TRUE(holds_binary_data(dir / "map.png"));
  EXPECT_TRUE(holds_binary_data(dir / "map.pgm"));
  EXPECT_FALSE(holds_binary_data(dir / "map.yaml"));
  EXPECT_FALSE(holds_binary_data(dir / "missing.yaml"));
  // A PGM whose first rows are all unknown (205): no control byte, but its signature.
  testing::write_bytes(dir / "grey.pgm", "P5\n4000 4000\n255\n" + std::string(5000, '\xcd'));
  EXPECT_TRUE(holds_binary_data(dir / "grey.pgm"));
  testing::write_bytes(dir / "p5.yaml", "P5: 3\n");  // a key named P5 is text
  EXPECT_FALSE(holds_binary_data(dir / "p5.yaml"));
}

}  // namespace
}  // namespace partslam::io
