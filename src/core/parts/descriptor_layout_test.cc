#include "core/parts/descriptor_layout.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace partslam {
namespace {

Points2 dictionary_points() { return {{-10.0, 2.0}, {30.0, -5.0}, {4.0, 20.0}}; }

TEST(DescriptorLayout, ExtentIsTheBoundingBoxGrownByOneCrop) {
  const CodecConfig c = dictionary_codec_config(dictionary_points());
  EXPECT_DOUBLE_EQ(c.dictionary_extent.x_min, -10.0 - 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.x_max, 30.0 + 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.y_min, -5.0 - 12.8);
  EXPECT_DOUBLE_EQ(c.dictionary_extent.y_max, 20.0 + 12.8);
  CodecConfig base;
  base.crop_size = 6.4;
  EXPECT_DOUBLE_EQ(dictionary_codec_config(dictionary_points(), base).dictionary_extent.x_min, -16.4);
  EXPECT_THROW(dictionary_codec_config({}), InputError);
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
