#include "core/parts/part_codec.h"

#include <climits>
#include <cmath>
#include <string>

#include "core/error.h"

namespace partslam {
namespace {

class BitWriter {
 public:
  explicit BitWriter(int total_bits) : bytes_((static_cast<std::size_t>(total_bits) + 7) / 8, 0) {}
  void put(std::uint32_t value, int bits) {
    for (int b = 0; b < bits; ++b, ++pos_) {
      if ((value >> b) & 1u) bytes_[pos_ >> 3] |= static_cast<std::uint8_t>(1u << (pos_ & 7));
    }
  }
  std::vector<std::uint8_t> take() { return std::move(bytes_); }

 private:
  std::vector<std::uint8_t> bytes_;
  std::size_t pos_ = 0;
};

class BitReader {
 public:
  explicit BitReader(const std::vector<std::uint8_t>& bytes) : bytes_(bytes) {}
  std::uint32_t get(int bits) {
    std::uint32_t value = 0;
    for (int b = 0; b < bits; ++b, ++pos_)
      value |= static_cast<std::uint32_t>((bytes_[pos_ >> 3] >> (pos_ & 7)) & 1u) << b;
    return value;
  }

 private:
  const std::vector<std::uint8_t>& bytes_;
  std::size_t pos_ = 0;
};

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

[[noreturn]] void fail(std::size_t part, const std::string& what) {
  throw InputError("part codec: part " + std::to_string(part) + ": " + what);
}

int keypoint_cells(const CodecConfig& c) {
  return static_cast<int>(std::lround(c.crop_size / c.keypoint_resolution));
}

// Cell index of a keypoint coordinate; the caller checks the range.
long long keypoint_cell(double x, const CodecConfig& c) {
  return std::llround((x + 0.5 * c.crop_size) / c.keypoint_resolution);
}

// Encodes one interval [lo, hi) of a keypoint box as (first cell, last cell).
void put_interval(BitWriter& w, double lo, double hi, const char* axis, std::size_t part,
                  const CodecConfig& c) {
  auto name = [&](const char* end) { return std::string("keypoint_box.") + axis + end; };
  auto outside = [&](double v) {
    return " = " + fmt(v) + " m lies outside the crop [" + fmt(-0.5 * c.crop_size) + ", " +
           fmt(0.5 * c.crop_size) + "] m";
  };
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) {
    fail(part, name("_min/max") + " = " + fmt(lo) + "/" + fmt(hi) + " m do not form a non-empty interval");
  }
  const long long cells = keypoint_cells(c);
  const long long first = keypoint_cell(lo, c);
  long long end = keypoint_cell(hi, c);
  if (first < 0 || first >= cells) fail(part, name("_min") + outside(lo));
  if (end > cells) fail(part, name("_max") + outside(hi));
  if (end <= first) end = first + 1;  // thinner than one cell: widen to one cell
  w.put(static_cast<std::uint32_t>(first), c.keypoint_bits);
  w.put(static_cast<std::uint32_t>(end - 1), c.keypoint_bits);
}

// Decodes an interval; returns false when the stored cells are inconsistent.
bool get_interval(BitReader& r, const CodecConfig& c, double& lo, double& hi) {
  const long long cells = keypoint_cells(c);
  const long long first = r.get(c.keypoint_bits);
  const long long last = r.get(c.keypoint_bits);
  if (first >= cells || last >= cells || last < first) return false;
  lo = static_cast<double>(first) * c.keypoint_resolution - 0.5 * c.crop_size;
  hi = static_cast<double>(last + 1) * c.keypoint_resolution - 0.5 * c.crop_size;
  return true;
}

std::uint32_t origin_index(double x, double x0, double step, int bits, const char* axis, std::size_t part) {
  const double q = std::round((x - x0) / step);
  const double top = static_cast<double>((1u << bits) - 1);
  if (!std::isfinite(x) || q < 0 || q > top) {
    fail(part, std::string("descriptor_box.") + axis + "_min = " + fmt(x) +
                   " m lies outside the dictionary extent (CodecConfig::dictionary_extent)");
  }
  return static_cast<std::uint32_t>(q);
}

}  // namespace

void validate(const CodecConfig& c) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(std::string("codec config: ") + name + " must be a positive finite number, got " +
                       fmt(v));
    }
  };
  auto bits = [](int v, int lo, int hi, const char* name) {
    if (v < lo || v > hi) {
      throw InputError(std::string("codec config: ") + name + " must be in [" + std::to_string(lo) + ", " +
                       std::to_string(hi) + "], got " + std::to_string(v));
    }
  };
  positive(c.crop_size, "crop_size");
  positive(c.keypoint_resolution, "keypoint_resolution");
  bits(c.keypoint_bits, 1, 16, "keypoint_bits");
  const double cells = std::round(c.crop_size / c.keypoint_resolution);
  if (cells < 1 || cells > static_cast<double>(1 << c.keypoint_bits)) {
    throw InputError("codec config: keypoint_bits = " + std::to_string(c.keypoint_bits) + " cannot hold " +
                     fmt(cells) + " cells of keypoint_resolution across crop_size");
  }
  const Box2& e = c.dictionary_extent;
  if (!std::isfinite(e.x_min) || !std::isfinite(e.x_max) || !std::isfinite(e.y_min) ||
      !std::isfinite(e.y_max) || !(e.width() > 0) || !(e.height() > 0)) {
    throw InputError(
        "codec config: dictionary_extent must be a finite non-empty box (set it to the dictionary "
        "map's bounding box)");
  }
  bits(c.origin_bits_x, 1, 16, "origin_bits_x");
  bits(c.origin_bits_y, 1, 16, "origin_bits_y");
  bits(c.rotation_bits, 0, 2, "rotation_bits");
  bits(c.score_bits, 0, 16, "score_bits");
  positive(c.score_max, "score_max");
}

int bits_per_part(const CodecConfig& c) {
  return 4 * c.keypoint_bits + c.origin_bits_x + c.origin_bits_y + c.rotation_bits + c.score_bits;
}

int packed_bits(int num_parts, const CodecConfig& c) {
  const int per_part = bits_per_part(c);
  if (num_parts < 0 || num_parts > INT_MAX / per_part) {
    throw InputError("part codec: invalid part count " + std::to_string(num_parts));
  }
  return num_parts * per_part;
}

Vec2 origin_step(const CodecConfig& c) {
  return {c.dictionary_extent.width() / static_cast<double>((1u << c.origin_bits_x) - 1),
          c.dictionary_extent.height() / static_cast<double>((1u << c.origin_bits_y) - 1)};
}

PackedDescriptor encode(const MapDescriptor& d, const CodecConfig& c) {
  validate(c);
  if (d.parts.size() > static_cast<std::size_t>(INT_MAX)) throw InputError("part codec: too many parts");
  const int total = packed_bits(static_cast<int>(d.parts.size()), c);
  const Vec2 step = origin_step(c);
  const double shape_tolerance = 1e-3 * c.keypoint_resolution;
  BitWriter w(total);
  for (std::size_t i = 0; i < d.parts.size(); ++i) {
    const Part& p = d.parts[i];
    if (p.rotation < 0 || p.rotation > 3)
      fail(i, "rotation = " + std::to_string(p.rotation) + " is not in {0..3}");
    if (c.rotation_bits == 0 && (p.rotation & 1)) {
      fail(i, "odd rotation " + std::to_string(p.rotation) + " needs rotation_bits >= 1");
    }
    const Box2 expected = place_rotated_box(p.keypoint_box, p.rotation, {0, 0});
    if (!(std::abs(p.descriptor_box.width() - expected.width()) <= shape_tolerance) ||
        !(std::abs(p.descriptor_box.height() - expected.height()) <= shape_tolerance)) {
      fail(i, "descriptor_box is " + fmt(p.descriptor_box.width()) + " x " + fmt(p.descriptor_box.height()) +
                  " m but the keypoint box turned by rotation is " + fmt(expected.width()) + " x " +
                  fmt(expected.height()) + " m");
    }
    put_interval(w, p.keypoint_box.x_min, p.keypoint_box.x_max, "x", i, c);
    put_interval(w, p.keypoint_box.y_min, p.keypoint_box.y_max, "y", i, c);
    w.put(origin_index(p.descriptor_box.x_min, c.dictionary_extent.x_min, step.x(), c.origin_bits_x, "x", i),
          c.origin_bits_x);
    w.put(origin_index(p.descriptor_box.y_min, c.dictionary_extent.y_min, step.y(), c.origin_bits_y, "y", i),
          c.origin_bits_y);
    w.put(static_cast<std::uint32_t>(p.rotation) & ((1u << c.rotation_bits) - 1), c.rotation_bits);
    if (c.score_bits > 0) {
      const double a = p.appearance_score;
      if (!std::isfinite(a) || a < 0 || a > c.score_max * (1 + 1e-9)) {
        fail(i, "appearance_score = " + fmt(a) + " lies outside [0, score_max = " + fmt(c.score_max) + "]");
      }
      const double levels = static_cast<double>((1u << c.score_bits) - 1);
      w.put(static_cast<std::uint32_t>(std::min(levels, std::round(a / c.score_max * levels))), c.score_bits);
    }
  }
  return {w.take(), total};
}

MapDescriptor decode(const PackedDescriptor& packed, const CodecConfig& c) {
  validate(c);
  const int per_part = bits_per_part(c);
  if (packed.bits < 0 || packed.bits % per_part != 0) {
    throw InputError("part codec: blob of " + std::to_string(packed.bits) +
                     " bits is not a whole number of " + std::to_string(per_part) + "-bit parts");
  }
  const std::size_t want_bytes = (static_cast<std::size_t>(packed.bits) + 7) / 8;
  if (packed.bytes.size() != want_bytes) {
    throw InputError("part codec: blob of " + std::to_string(packed.bits) + " bits must have " +
                     std::to_string(want_bytes) + " bytes, got " + std::to_string(packed.bytes.size()));
  }
  if (packed.bits % 8 != 0 && (packed.bytes.back() >> (packed.bits % 8)) != 0) {
    throw InputError("part codec: padding bits of the last byte are not zero (corrupt blob)");
  }
  const Vec2 step = origin_step(c);
  const double score_levels = static_cast<double>((1u << c.score_bits) - 1);
  BitReader r(packed.bytes);
  MapDescriptor d;
  d.parts.resize(static_cast<std::size_t>(packed.bits / per_part));
  for (std::size_t i = 0; i < d.parts.size(); ++i) {
    Part& p = d.parts[i];
    Box2& k = p.keypoint_box;
    if (!get_interval(r, c, k.x_min, k.x_max) || !get_interval(r, c, k.y_min, k.y_max)) {
      fail(i, "keypoint cells out of range (corrupt blob or wrong codec config)");
    }
    const double ox = c.dictionary_extent.x_min + step.x() * r.get(c.origin_bits_x);
    const double oy = c.dictionary_extent.y_min + step.y() * r.get(c.origin_bits_y);
    p.rotation = static_cast<int>(r.get(c.rotation_bits));
    p.appearance_score = c.score_bits > 0 ? r.get(c.score_bits) / score_levels * c.score_max : c.score_max;
    p.descriptor_box = place_rotated_box(k, p.rotation, {ox, oy});
  }
  return d;
}

MapDescriptor decode(const std::vector<std::uint8_t>& bytes, int num_parts, const CodecConfig& c) {
  validate(c);
  return decode(PackedDescriptor{bytes, packed_bits(num_parts, c)}, c);
}

}  // namespace partslam
