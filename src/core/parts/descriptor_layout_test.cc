#include "core/parts/descriptor_layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

Points2 dictionary_points() { return {{-10.0, 2.0}, {30.0, -5.0}, {4.0, 20.0}}; }

bool on_grid(double x, double cell) { return std::abs(x / cell - std::round(x / cell)) < 1e-9; }

TEST(DescriptorLayout, ExtentCoversTheBoundingBoxGrownByOneCropOnTheKeypointGrid) {
  const Points2 points = {{-10.03, 2.0}, {30.0, -5.07}, {4.0, 20.0}};
  const CodecConfig c = dictionary_codec_config(points);
  const Box2& e = c.dictionary_extent;
  EXPECT_LE(e.x_min, -10.03 - 12.8);
  EXPECT_GT(e.x_min, -10.03 - 12.8 - 0.1);
  EXPECT_GE(e.x_max, 30.0 + 12.8);
  EXPECT_LE(e.y_min, -5.07 - 12.8);
  EXPECT_GE(e.y_max, 20.0 + 12.8);
  const Vec2 step = origin_step(c);
  EXPECT_TRUE(on_grid(e.x_min, 0.1) && on_grid(e.y_min, 0.1));
  EXPECT_TRUE(on_grid(step.x(), 0.1) && on_grid(step.y(), 0.1));
  EXPECT_LT(step.x(), (30.0 - -10.03 + 25.6) / 127 + 0.1);  // no coarser than needed
  CodecConfig base;
  base.crop_size = 6.4;
  EXPECT_NEAR(dictionary_codec_config(points, base).dictionary_extent.x_min, -16.5, 1e-9);
  EXPECT_THROW(dictionary_codec_config({}), InputError);
  base.origin_bits_x = 40;
  EXPECT_THROW(dictionary_codec_config(points, base), InputError);
}

TEST(DescriptorLayout, DecodedDescriptorBoxesLieOnTheMatchersGrid) {
  const Points2 points = {{-10.03, 2.0}, {30.0, -5.07}, {4.0, 20.0}};
  const CodecConfig c = descriptor_codec_config(points, 3);
  const Box2 keypoint{-1.23, 1.07, -0.55, 0.61};
  MapDescriptor d;
  for (int r = 0; r < 4; ++r) d.parts.push_back({keypoint, place_rotated_box(keypoint, r, {3.37 + r, -4.21}), 1, r});
  for (const Part& p : decode(encode(d, c), c).parts) {
    for (double v : {p.descriptor_box.x_min, p.descriptor_box.x_max, p.descriptor_box.y_min, p.descriptor_box.y_max})
      EXPECT_TRUE(on_grid(v, 0.1)) << v;
  }
}

TEST(DescriptorLayout, SchemaVersionOneRuleIsTheUnsnappedGrownBox) {
  const CodecConfig c = descriptor_codec_config_v1(dictionary_points(), 3);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.x_min, -10.0 - 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.x_max, 30.0 + 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.y_min, -5.0 - 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.y_max, 20.0 + 12.8);
  EXPECT_EQ(c.score_bits, 0);
  EXPECT_EQ(descriptor_codec_config_v1(dictionary_points(), 100).score_bits, kQueryScoreBits);
}

TEST(DescriptorLayout, OnlyQueryListsStoreScores) {
  EXPECT_EQ(score_bits_for_parts(1), 0);
  EXPECT_EQ(score_bits_for_parts(kMaxUnscoredParts), 0);
  EXPECT_EQ(score_bits_for_parts(kMaxUnscoredParts + 1), kQueryScoreBits);
  EXPECT_THROW(score_bits_for_parts(0), InputError);
  EXPECT_EQ(bits_per_part(descriptor_codec_config(dictionary_points(), 3)), 44);
  EXPECT_EQ(bits_per_part(descriptor_codec_config(dictionary_points(), 100)), 44 + kQueryScoreBits);
}

TEST(DescriptorLayout, StoredDescriptorsRoundTripWithTheirScores) {
  const Box2 keypoint{-1.0, 1.0, -0.5, 0.5};
  const Part part{keypoint, place_rotated_box(keypoint, 1, {3.0, 4.0}), 0.6, 1};
  const MapDescriptor descriptor{{part, part}};
  for (int k : {2, 100}) {
    const CodecConfig c = descriptor_codec_config(dictionary_points(), k);
    const MapDescriptor back = decode_stored(encode(descriptor, c), k, c);
    ASSERT_EQ(back.parts.size(), 2u);
    EXPECT_EQ(back.parts[0].rotation, 1);
    EXPECT_NEAR(back.parts[0].descriptor_box.x_min, 3.0, origin_step(c).x());
    EXPECT_NEAR(back.parts[0].appearance_score, k == 2 ? 1.0 : 0.6, 1.0 / 255);
  }
  const CodecConfig c = descriptor_codec_config(dictionary_points(), 1);
  EXPECT_THROW(decode_stored(encode(descriptor, c), 1, c), InputError);  // two parts under K = 1
}

}  // namespace
}  // namespace partslam
