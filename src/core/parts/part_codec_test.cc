#include "core/parts/part_codec.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"

namespace partslam {
namespace {

CodecConfig test_config() {
  CodecConfig c;
  c.dictionary_extent = {-20.0, 30.8, -10.0, 15.4};  // 50.8 m x 25.4 m: steps 0.4 m and 0.2 m
  return c;
}

Part make_part(const Box2& keypoint, int rotation, const Vec2& origin, double score = 0.5) {
  return {keypoint, place_rotated_box(keypoint, rotation, origin), score, rotation};
}

TEST(PartCodec, BitBudget) {
  CodecConfig c = test_config();
  EXPECT_EQ(bits_per_part(c), 44);  // paper's 42 + 2 rotation bits
  for (int k = 1; k <= 5; ++k) EXPECT_EQ(packed_bits(k, c), 44 * k);
  c.rotation_bits = 0;
  EXPECT_EQ(bits_per_part(c), 42);  // the paper's literal layout
  EXPECT_EQ(packed_bits(3, c), 126);
  c.rotation_bits = 2;
  c.score_bits = 4;
  EXPECT_EQ(bits_per_part(c), 48);
  const Vec2 step = origin_step(test_config());
  EXPECT_NEAR(step.x(), 0.4, 1e-12);
  EXPECT_NEAR(step.y(), 0.2, 1e-12);
}

TEST(PartCodec, KnownBitLayout) {
  const CodecConfig c = test_config();
  // x cells [1, 3) -> fields 1, 2; y cells [0, 128) -> 0, 127; origin lattice (2, 5); rotation 3.
  const Part p = make_part({-6.3, -6.1, -6.4, 6.4}, 3, {-20.0 + 2 * 0.4, -10.0 + 5 * 0.2});
  const PackedDescriptor packed = encode(MapDescriptor{{p}}, c);
  ASSERT_EQ(packed.bits, 44);
  ASSERT_EQ(packed.bytes.size(), 6u);
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < packed.bytes.size(); ++i) v |= std::uint64_t{packed.bytes[i]} << (8 * i);
  const std::uint64_t expected = 1ull | (2ull << 7) | (0ull << 14) | (127ull << 21) | (2ull << 28) | (5ull << 35) |
                                 (3ull << 42);
  EXPECT_EQ(v, expected);
}

TEST(PartCodec, ExactRoundTripOnTheLattice) {
  const CodecConfig c = test_config();
  MapDescriptor d;
  d.parts.push_back(make_part({-6.4, 6.4, -6.4, 6.4}, 0, {-20.0, -10.0}));  // whole crop, extent corner
  d.parts.push_back(make_part({1.2, 3.5, -2.0, 0.1}, 1, {-20.0 + 100 * 0.4, -10.0 + 3 * 0.2}));
  d.parts.push_back(make_part({6.3, 6.4, -6.4, -6.3}, 2, {30.8, 15.4}));  // far lattice corner
  d.parts.push_back(make_part({-0.5, 0.5, 2.0, 2.6}, 3, {0.0 - 20 + 50 * 0.4, -10.0 + 64 * 0.2}));
  const MapDescriptor back = decode(encode(d, c), c);
  ASSERT_EQ(back.parts.size(), d.parts.size());
  for (std::size_t i = 0; i < d.parts.size(); ++i) {
    const Part &a = d.parts[i], &b = back.parts[i];
    EXPECT_EQ(b.rotation, a.rotation);
    for (auto [x, y] : {std::pair{a.keypoint_box.x_min, b.keypoint_box.x_min},
                        {a.keypoint_box.x_max, b.keypoint_box.x_max}, {a.keypoint_box.y_min, b.keypoint_box.y_min},
                        {a.keypoint_box.y_max, b.keypoint_box.y_max}, {a.descriptor_box.x_min, b.descriptor_box.x_min},
                        {a.descriptor_box.x_max, b.descriptor_box.x_max}, {a.descriptor_box.y_min, b.descriptor_box.y_min},
                        {a.descriptor_box.y_max, b.descriptor_box.y_max}}) {
      EXPECT_NEAR(x, y, 1e-9) << "part " << i;
    }
    EXPECT_DOUBLE_EQ(b.appearance_score, c.score_max);  // not stored with score_bits = 0
  }
}

TEST(PartCodec, RandomRoundTripWithinQuantisation) {
  CodecConfig c = test_config();
  c.score_bits = 5;
  const Vec2 step = origin_step(c);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    MapDescriptor d;
    for (int k = 0; k < 1 + trial % 5; ++k) {
      const double x0 = -6.4 + 12.0 * u(rng), y0 = -6.4 + 12.0 * u(rng);
      const Box2 kp{x0, std::min(6.4, x0 + 0.2 + 6 * u(rng)), y0, std::min(6.4, y0 + 0.2 + 6 * u(rng))};
      const Vec2 origin{-20.0 + 50.8 * u(rng), -10.0 + 25.4 * u(rng)};
      d.parts.push_back(make_part(kp, static_cast<int>(rng() % 4), origin, u(rng)));
    }
    const PackedDescriptor packed = encode(d, c);
    EXPECT_EQ(packed.bits, 49 * static_cast<int>(d.parts.size()));  // 44 + 5 score bits
    const MapDescriptor back = decode(packed, c);
    ASSERT_EQ(back.parts.size(), d.parts.size());
    for (std::size_t i = 0; i < d.parts.size(); ++i) {
      const Part &a = d.parts[i], &b = back.parts[i];
      EXPECT_EQ(b.rotation, a.rotation);
      EXPECT_NEAR(b.keypoint_box.x_min, a.keypoint_box.x_min, 0.05 + 1e-9);
      EXPECT_NEAR(b.keypoint_box.x_max, a.keypoint_box.x_max, 0.05 + 1e-9);
      EXPECT_NEAR(b.keypoint_box.y_min, a.keypoint_box.y_min, 0.05 + 1e-9);
      EXPECT_NEAR(b.keypoint_box.y_max, a.keypoint_box.y_max, 0.05 + 1e-9);
      EXPECT_NEAR(b.descriptor_box.x_min, a.descriptor_box.x_min, step.x() / 2 + 1e-9);
      EXPECT_NEAR(b.descriptor_box.y_min, a.descriptor_box.y_min, step.y() / 2 + 1e-9);
      EXPECT_NEAR(b.descriptor_box.width(), (a.rotation & 1 ? b.keypoint_box.height() : b.keypoint_box.width()), 1e-9);
      EXPECT_NEAR(b.descriptor_box.height(), (a.rotation & 1 ? b.keypoint_box.width() : b.keypoint_box.height()), 1e-9);
      EXPECT_NEAR(b.appearance_score, a.appearance_score, 0.5 / 31 + 1e-9);
    }
    // Idempotent: decoded values sit on the lattice.
    const MapDescriptor again = decode(encode(back, c), c);
    for (std::size_t i = 0; i < d.parts.size(); ++i) {
      EXPECT_NEAR(again.parts[i].descriptor_box.x_min, back.parts[i].descriptor_box.x_min, 1e-9);
      EXPECT_NEAR(again.parts[i].keypoint_box.y_max, back.parts[i].keypoint_box.y_max, 1e-9);
      EXPECT_EQ(again.parts[i].appearance_score, back.parts[i].appearance_score);
    }
  }
}

TEST(PartCodec, ScoreBoundsAndRotationBits) {
  CodecConfig c = test_config();
  c.score_bits = 3;
  MapDescriptor d{{make_part({0, 1, 0, 1}, 1, {0, 0}, 0.0), make_part({0, 1, 0, 1}, 2, {0, 0}, 1.0)}};
  MapDescriptor back = decode(encode(d, c), c);
  EXPECT_DOUBLE_EQ(back.parts[0].appearance_score, 0.0);
  EXPECT_DOUBLE_EQ(back.parts[1].appearance_score, 1.0);
  c.rotation_bits = 1;  // keeps the parity (the descriptor box shape), loses the half turn
  back = decode(encode(d, c), c);
  EXPECT_EQ(back.parts[0].rotation, 1);
  EXPECT_EQ(back.parts[1].rotation, 0);
  c.rotation_bits = 0;
  EXPECT_THROW(encode(d, c), InputError);  // odd rotation cannot be represented
  d.parts.erase(d.parts.begin());
  EXPECT_EQ(decode(encode(d, c), c).parts[0].rotation, 0);
}

TEST(PartCodec, ThinBoxIsWidenedToOneCell) {
  const CodecConfig c = test_config();
  const MapDescriptor back = decode(encode(MapDescriptor{{make_part({1.0, 1.02, 0, 1}, 0, {0, 0})}}, c), c);
  EXPECT_NEAR(back.parts[0].keypoint_box.x_min, 1.0, 1e-9);
  EXPECT_NEAR(back.parts[0].keypoint_box.x_max, 1.1, 1e-9);
}

TEST(PartCodec, EmptyDescriptor) {
  const PackedDescriptor packed = encode(MapDescriptor{}, test_config());
  EXPECT_EQ(packed.bits, 0);
  EXPECT_TRUE(packed.bytes.empty());
  EXPECT_TRUE(decode(packed, test_config()).parts.empty());
}

TEST(PartCodec, EncodeRejectsBadParts) {
  const CodecConfig c = test_config();
  auto bad = [&](const Part& p) { EXPECT_THROW(encode(MapDescriptor{{p}}, c), InputError); };
  bad(make_part({-6.6, 0, 0, 1}, 0, {0, 0}));          // keypoint left of the crop
  bad(make_part({0, 6.6, 0, 1}, 0, {0, 0}));           // keypoint right of the crop
  bad(make_part({0, 1, 1, 1}, 0, {0, 0}));             // empty
  bad(make_part({0, 1, 0, 1}, 0, {-20.5, 0}));         // origin outside the dictionary
  bad(make_part({0, 1, 0, 1}, 0, {0, 15.4 + 0.11}));   // more than half a step past the top
  bad(make_part({0, 1, 0, 1}, 4, {0, 0}));             // rotation outside {0..3}
  Part p = make_part({0, 1, 0, 2}, 1, {0, 0});
  p.descriptor_box = {0, 1, 0, 2};  // shape not turned with the rotation
  bad(p);
  CodecConfig scored = c;
  scored.score_bits = 4;
  EXPECT_THROW(encode(MapDescriptor{{make_part({0, 1, 0, 1}, 0, {0, 0}, 1.5)}}, scored), InputError);
  EXPECT_THROW(encode(MapDescriptor{{make_part({0, 1, 0, 1}, 0, {0, 0}, -0.1)}}, scored), InputError);
}

TEST(PartCodec, DecodeRejectsBadBlobs) {
  const CodecConfig c = test_config();
  const MapDescriptor d{{make_part({0, 1, 0, 1}, 0, {0, 0}), make_part({-1, 1, -2, 0}, 3, {1, 1}),
                         make_part({2, 3, 4, 6}, 2, {5, 5})}};
  const PackedDescriptor good = encode(d, c);
  ASSERT_EQ(good.bits, 132);
  ASSERT_EQ(good.bytes.size(), 17u);
  PackedDescriptor p = good;
  p.bytes.pop_back();
  EXPECT_THROW(decode(p, c), InputError);  // too short
  p = good;
  p.bytes.push_back(0);
  EXPECT_THROW(decode(p, c), InputError);  // too long
  p = good;
  p.bits = 131;
  EXPECT_THROW(decode(p, c), InputError);  // not a whole number of parts
  p = good;
  p.bytes.back() |= 0x80;
  EXPECT_THROW(decode(p, c), InputError);  // padding bits set
  p = good;
  p.bytes[0] = 0x7f;  // x_begin = 127 > x_last
  EXPECT_THROW(decode(p, c), InputError);
  EXPECT_THROW(decode(good.bytes, 2, c), InputError);  // wrong part count for the blob
  EXPECT_EQ(decode(good.bytes, 3, c).parts.size(), 3u);
}

TEST(PartCodec, ValidateNamesTheField) {
  CodecConfig c = test_config();
  c.keypoint_bits = 6;  // 64 cells cannot hold 12.8 m at 0.1 m
  EXPECT_THROW(validate(c), InputError);
  c = CodecConfig{};  // no dictionary extent
  try {
    validate(c);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dictionary_extent"), std::string::npos);
  }
  c = test_config();
  c.score_bits = 17;
  EXPECT_THROW(validate(c), InputError);
}

TEST(SelectTopParts, KeepsTheBestKInOrder) {
  std::vector<Part> parts(5);
  const double scores[] = {0.2, 0.9, 0.5, 0.9, 0.1};
  for (int i = 0; i < 5; ++i) parts[i].appearance_score = scores[i], parts[i].rotation = i;
  const MapDescriptor d = select_top_parts(parts, 3);
  ASSERT_EQ(d.parts.size(), 3u);
  EXPECT_EQ(d.parts[0].rotation, 1);  // ties keep input order
  EXPECT_EQ(d.parts[1].rotation, 3);
  EXPECT_EQ(d.parts[2].rotation, 2);
  EXPECT_EQ(select_top_parts(parts, 9).parts.size(), 5u);
  EXPECT_THROW(select_top_parts(parts, -1), InputError);
}

}  // namespace
}  // namespace partslam
