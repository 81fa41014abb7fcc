#include "core/parts/cpd.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "core/error.h"
#include "core/maps/local_shape.h"
#include "core/maps/submap.h"
#include "core/timing.h"

namespace partslam {
namespace {

// Uniform double in [0, 1) from 53 random bits: identical on every standard library.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

bool overlaps(const Box2& a, const Box2& b) {
  return std::min(a.x_max, b.x_max) > std::max(a.x_min, b.x_min) &&
         std::min(a.y_max, b.y_max) > std::max(a.y_min, b.y_min);
}

// Crops include their boundary, so a box snapped to the lattice keeps the points on its far edges.
bool inside_closed(const Box2& b, const Vec2& p) {
  return p.x() >= b.x_min && p.x() <= b.x_max && p.y() >= b.y_min && p.y() <= b.y_max;
}

// Random partitions of the map's bounding box into grids of boxes (RVP). Boxes are snapped outward to the
// keypoint lattice (0.1 m) so equal boxes dedupe and encode exactly.
std::vector<Box2> candidate_boxes(const Points2& points, const CpdConfig& config, std::mt19937_64& rng) {
  const Box2 bb = bounding_box(points);
  const double q = kMapResolution;
  const auto snap_lo = [q](double v) { return std::floor(v / q + 1e-9) * q; };
  const auto snap_hi = [q](double v) { return std::ceil(v / q - 1e-9) * q; };
  std::set<std::tuple<long, long, long, long>> seen;
  std::vector<Box2> out;
  const double W = std::max(bb.width(), q), H = std::max(bb.height(), q);
  for (int p = 0; p < config.partitions; ++p) {
    const double span = config.max_cell_fraction - config.min_cell_fraction;
    const double cw = W * (config.min_cell_fraction + span * uniform01(rng));
    const double ch = H * (config.min_cell_fraction + span * uniform01(rng));
    const double ox = bb.x_min - cw * uniform01(rng), oy = bb.y_min - ch * uniform01(rng);
    for (double x = ox; x < bb.x_max; x += cw) {
      for (double y = oy; y < bb.y_max; y += ch) {
        Box2 b{snap_lo(std::max(x, bb.x_min)), snap_hi(std::min(x + cw, bb.x_max)),
               snap_lo(std::max(y, bb.y_min)), snap_hi(std::min(y + ch, bb.y_max))};
        const auto key = std::make_tuple(std::lround(b.x_min / q), std::lround(b.x_max / q), std::lround(b.y_min / q),
                                         std::lround(b.y_max / q));
        if (b.area() <= 0 || !seen.insert(key).second) continue;
        out.push_back(b);
      }
    }
  }
  return out;
}

// Squares of every configured size centred on each corner, clipped to the codec's crop and snapped outward to
// the keypoint lattice; duplicates dropped. Strongest corner first, sizes in the configured order.
std::vector<Box2> corner_boxes(const Points2& points, const CpdConfig& config) {
  const double q = kMapResolution;
  const auto snap_lo = [q](double v) { return std::floor(v / q + 1e-9) * q; };
  const auto snap_hi = [q](double v) { return std::ceil(v / q - 1e-9) * q; };
  const double e = config.crop_extent;
  std::set<std::tuple<long, long, long, long>> seen;
  std::vector<Box2> out;
  for (const Vec2& c : find_corners(points, config)) {
    for (double side : config.box_sizes) {
      const double h = side / 2;
      Box2 b{snap_lo(std::max(c.x() - h, -e)), snap_hi(std::min(c.x() + h, e)), snap_lo(std::max(c.y() - h, -e)),
             snap_hi(std::min(c.y() + h, e))};
      const auto key = std::make_tuple(std::lround(b.x_min / q), std::lround(b.x_max / q), std::lround(b.y_min / q),
                                       std::lround(b.y_max / q));
      if (b.area() <= 0 || !seen.insert(key).second) continue;
      out.push_back(b);
    }
  }
  return out;
}

Part describe(const Box2& keypoint_box, const Vec2& crop_origin, const DmmResult& fit, int crop_points) {
  Part part;
  part.keypoint_box = keypoint_box;
  part.appearance_score = crop_points > 0 ? static_cast<double>(fit.inliers) / crop_points : 0.0;
  const double quarter = std::numbers::pi / 2;
  part.rotation = static_cast<int>(std::lround(fit.T_map_query.theta / quarter)) & 3;
  // The keypoint box's centre, carried into the dictionary by T_dict_crop; the descriptor box is the keypoint
  // box turned by the nearest quarter turn, centred there.
  const Vec2 centre{(keypoint_box.x_min + keypoint_box.x_max) / 2, (keypoint_box.y_min + keypoint_box.y_max) / 2};
  const Vec2 c_dict = fit.T_map_query * (centre - crop_origin);
  const bool swap = part.rotation & 1;
  const double w = swap ? keypoint_box.height() : keypoint_box.width();
  const double h = swap ? keypoint_box.width() : keypoint_box.height();
  part.descriptor_box = {c_dict.x() - w / 2, c_dict.x() + w / 2, c_dict.y() - h / 2, c_dict.y() + h / 2};
  return part;
}

}  // namespace

Points2 find_corners(const Points2& map_points, const CpdConfig& config) {
  const Points2 pts = voxel_downsample(map_points, kMapResolution);
  const std::vector<LocalShape> shapes = local_shapes(pts, config.corner_radius);
  struct Scored {
    double response;
    Vec2 p;
  };
  std::vector<Scored> scored;
  // The smaller eigenvalue of the neighbourhood's scatter is large only where walls meet.
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (shapes[k].neighbours >= 8) scored.push_back({shapes[k].lambda_min, pts[k]});
  // Strongest first; ties by position so the order never depends on the input order.
  std::sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) {
    if (a.response != b.response) return a.response > b.response;
    if (a.p.x() != b.p.x()) return a.p.x() < b.p.x();
    return a.p.y() < b.p.y();
  });
  Points2 corners;
  const double s2 = config.corner_spacing * config.corner_spacing;
  for (const Scored& s : scored) {
    if (static_cast<int>(corners.size()) >= config.corners) break;
    if (std::any_of(corners.begin(), corners.end(), [&](const Vec2& c) { return (c - s.p).squaredNorm() < s2; }))
      continue;
    corners.push_back(s.p);
  }
  return corners;
}

void validate(const CpdConfig& c) {
  if (c.max_parts < 1 || c.max_parts > 10000) throw InputError("cpd: max_parts must be in [1, 10000]");
  if (c.partitions < 1 || c.partitions > 100000) throw InputError("cpd: partitions must be in [1, 100000]");
  if (!(c.min_cell_fraction > 0.01) || !(c.max_cell_fraction >= c.min_cell_fraction) || c.max_cell_fraction > 10)
    throw InputError("cpd: need 0.01 < min_cell_fraction <= max_cell_fraction <= 10");
  if (!(c.t_size >= 0 && c.t_size <= 1)) throw InputError("cpd: t_size must be in [0, 1]");
  if (c.min_crop_points < 1) throw InputError("cpd: min_crop_points must be >= 1");
  if (!(c.crop_resolution > 0) || c.crop_resolution > 10) throw InputError("cpd: crop_resolution must be in (0, 10] m");
  if (c.candidates == CandidateMode::kCorners) {
    if (c.corners < 1 || c.corners > 10000) throw InputError("cpd: corners must be in [1, 10000]");
    if (c.box_sizes.empty()) throw InputError("cpd: box_sizes must list at least one size");
    for (double s : c.box_sizes)
      if (!(s >= 0.2 && s <= 100)) throw InputError("cpd: every box size must be in [0.2, 100] m");
    if (!(c.corner_radius >= 0.1 && c.corner_radius <= 10)) throw InputError("cpd: corner_radius must be in [0.1, 10] m");
    if (!(c.corner_spacing >= 0 && c.corner_spacing <= 100)) throw InputError("cpd: corner_spacing must be in [0, 100] m");
    if (!(c.crop_extent > 0 && c.crop_extent <= 100)) throw InputError("cpd: crop_extent must be in (0, 100] m");
  }
  validate(c.dmm);
}

PreparedDictionary prepare_dictionary(const Points2& dictionary_points, const CpdConfig& config) {
  validate(config);
  if (dictionary_points.empty()) throw InputError("cpd: the dictionary map has no points");
  return {prepare_map(dictionary_points, config.dmm), bounding_box(dictionary_points)};
}

CpdResult discover_parts(const Points2& map_points, const PreparedDictionary& dictionary, const CpdConfig& config,
                         std::uint64_t map_key) {
  validate(config);
  CpdResult result;
  if (static_cast<int>(map_points.size()) < config.min_crop_points) return result;
  std::mt19937_64 rng(config.seed * 0x9E3779B97F4A7C15ULL ^ (map_key + 0x632BE59BD9B4E019ULL));
  const std::vector<Box2> boxes = config.candidates == CandidateMode::kCorners ? corner_boxes(map_points, config)
                                                                                : candidate_boxes(map_points, config, rng);
  result.stats.candidates = static_cast<int>(boxes.size());

  // MC (point share) is known before matching.
  struct Candidate {
    Box2 box;
    Points2 crop;
  };
  std::vector<Candidate> candidates;
  const double n = static_cast<double>(map_points.size());
  for (const Box2& b : boxes) {
    Points2 crop;
    for (const Vec2& p : map_points)
      if (inside_closed(b, p)) crop.push_back(p);
    if (static_cast<int>(crop.size()) < config.min_crop_points) continue;
    if (config.maximality == MaximalityMode::kPointShare && crop.size() < config.t_size * n) continue;
    candidates.push_back({b, std::move(crop)});
  }
  result.stats.passed_mc = static_cast<int>(candidates.size());
  // Shuffle (seeded) so the matched ones are a fair sample of all candidates, and AS ties (common: a small
  // crop often fits the dictionary perfectly) go to a random candidate. For corners this beats keeping the
  // strongest corners first (docs/NOTES.md has the comparison).
  for (std::size_t i = candidates.size(); i > 1; --i) std::swap(candidates[i - 1], candidates[rng() % i]);

  // AS (Eq. 2): exact search of every crop against the whole dictionary.
  std::vector<Part> scored;
  for (Candidate& c : candidates) {
    if (static_cast<int>(scored.size()) >= config.max_parts) break;
    const Vec2 origin = centroid(c.crop);
    for (Vec2& p : c.crop) p -= origin;
    const Points2 crop = voxel_downsample(c.crop, config.crop_resolution);
    const DmmResult fit = match_dmm(prepare_query(crop, config.dmm), dictionary.map);
    ++result.stats.matched;
    Part part = describe(c.box, origin, fit, static_cast<int>(crop.size()));
    if (config.maximality == MaximalityMode::kInlierShare && part.appearance_score < config.t_size) continue;
    if (config.maximality == MaximalityMode::kPointShare) result.stats.passed_mc = result.stats.matched;
    scored.push_back(part);
  }
  // Best AS first; ties keep the (seeded) candidate order.
  std::stable_sort(scored.begin(), scored.end(),
                   [](const Part& a, const Part& b) { return a.appearance_score > b.appearance_score; });

  // GC: greedily keep a part when its descriptor box overlaps those of all parts kept so far.
  for (const Part& p : scored) {
    const bool consistent =
        !config.geometric_consistency ||
        std::all_of(result.parts.begin(), result.parts.end(),
                    [&](const Part& q) { return overlaps(p.descriptor_box, q.descriptor_box); });
    if (consistent) result.parts.push_back(p);
  }
  result.stats.passed_gc = static_cast<int>(result.parts.size());
  return result;
}

std::vector<CpdResult> discover_parts_many(const std::vector<const Points2*>& maps,
                                           const std::vector<std::uint64_t>& map_keys,
                                           const PreparedDictionary& dictionary, const CpdConfig& config,
                                           int num_threads, const Progress& progress) {
  if (maps.size() != map_keys.size()) throw InputError("cpd: one key per map is required");
  validate(config);
  std::vector<CpdResult> results(maps.size());
  parallel_for(
      maps.size(), num_threads,
      [&](std::size_t i) {
        const auto t0 = Clock::now();
        results[i] = discover_parts(*maps[i], dictionary, config, map_keys[i]);
        results[i].ms = ms_since(t0);
      },
      "parts (CPD)", progress);
  return results;
}

}  // namespace partslam
