// The map database's blob encodings (io/store/blob_codec.h): little-endian, lengths and values checked.
#include "io/store/blob_codec.h"

#include <gtest/gtest.h>

#include <span>

#include "core/error.h"

namespace partslam::io {
namespace {

TEST(BlobCodec, LittleEndianAndLengthChecked) {
  const Bytes bytes = encode_points_f32({{1.0, -2.0}}, "test");
  EXPECT_EQ(bytes, (Bytes{0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xc0}));
  EXPECT_EQ(encode_f64({1.0}), (Bytes{0, 0, 0, 0, 0, 0, 0xf0, 0x3f}));
  EXPECT_EQ(decode_points_f32(bytes, 1, "test"), (Points2{{1.0, -2.0}}));
  EXPECT_THROW(decode_points_f32(bytes, 2, "test"), InputError);
  EXPECT_THROW(decode_f64(std::span(bytes).first(7), "test"), InputError);
  EXPECT_THROW(encode_points_f32({{1e39, 0.0}}, "test"), InputError);
  EXPECT_THROW(decode_points_f32(Bytes{0, 0, 0xc0, 0x7f, 0, 0, 0, 0}, 1, "test"), InputError);  // NaN
}

}  // namespace
}  // namespace partslam::io
