// part_stats INPUT_LOG DICTIONARY_LOG: why descriptor matching works or not on a data set. Runs CPD with the
// default configuration on every submap of INPUT against DICTIONARY and prints, over all relevant pairs
// (R = 2 m, G = 20 m):
//   repeat:  the share of a map's parts that have a part of the same size centred within 0.5 m of the same
//            place (ground-truth relative pose) in the other map,
//   same spot: of those, the share whose descriptor boxes overlap with f_RS > 0.5 (the part "hashes" alike),
// and how crowded the dictionary is: the share of all descriptor centres in the busiest 1/128 of its extent.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <vector>

#include "core/parts/cpd.h"
#include "core/parts/descriptor_matcher.h"
#include "core/maps/dictionary.h"
#include "core/maps/submap.h"
#include "core/evaluation/tasks.h"
#include "io/logs/scan_source.h"

using namespace partslam;

namespace {

Vec2 centre(const Box2& b) { return {(b.x_min + b.x_max) / 2, (b.y_min + b.y_max) / 2}; }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: part_stats INPUT_LOG DICTIONARY_LOG (CARMEN logs or sim[:SEED])\n");
    return 2;
  }
  try {
    const io::ScanSource input = io::load_scan_source(argv[1]), dict = io::load_scan_source(argv[2]);
    const Submaps maps = build_submaps(input.scans);
    const Dictionary dictionary = build_dictionary(dict.name, dict.scans);
    const CpdConfig config;
    const PreparedDictionary prepared = prepare_dictionary(dictionary.points, config);
    std::vector<const Points2*> points;
    std::vector<std::uint64_t> keys;
    for (std::size_t i = 0; i < maps.size(); ++i) points.push_back(&maps[i].points), keys.push_back(i);
    const std::vector<CpdResult> parts = discover_parts_many(points, keys, prepared, config, 2);

    double total = 0, as = 0;
    constexpr int kCols = 16, kRows = 8;
    std::vector<int> cells(kCols * kRows, 0);
    const Box2& e = prepared.extent;
    for (const CpdResult& r : parts) {
      for (const Part& p : r.parts) {
        ++total, as += p.appearance_score;
        const Vec2 c = centre(p.descriptor_box);
        const int i = std::clamp(static_cast<int>((c.x() - e.x_min) / e.width() * kCols), 0, kCols - 1);
        const int j = std::clamp(static_cast<int>((c.y() - e.y_min) / e.height() * kRows), 0, kRows - 1);
        ++cells[j * kCols + i];
      }
    }
    long considered = 0, repeated = 0, same_spot = 0;
    for (const RelevantPair& pair : relevant_pairs(maps, TaskConfig{})) {
      const Pose2 T_other_this = maps[pair.global].T_world_map.inverse() * maps[pair.query].T_world_map;
      for (const Part& a : parts[pair.query].parts) {
        ++considered;
        const Vec2 where = T_other_this * centre(a.keypoint_box);
        const Part* match = nullptr;
        double best = 0.5;
        for (const Part& b : parts[pair.global].parts) {
          const double side_a = std::max(a.keypoint_box.width(), a.keypoint_box.height());
          const double side_b = std::max(b.keypoint_box.width(), b.keypoint_box.height());
          const double d = (centre(b.keypoint_box) - where).norm();
          if (std::abs(side_a - side_b) < 0.5 && d <= best) best = d, match = &b;
        }
        if (match == nullptr) continue;
        ++repeated;
        same_spot += region_similarity(a.descriptor_box, match->descriptor_box) > 0.5;
      }
    }
    std::printf("%s vs dictionary %s: %zu maps, %.1f parts per map, mean AS %.3f\n", input.name.c_str(),
                dict.name.c_str(), maps.size(), total / static_cast<double>(maps.size()), as / std::max(total, 1.0));
    std::printf("relevant pairs: repeat %.1f %% of %ld parts, same spot %.1f %% of those\n",
                100.0 * static_cast<double>(repeated) / std::max(considered, 1L), considered,
                100.0 * static_cast<double>(same_spot) / std::max(repeated, 1L));
    std::printf("dictionary %.1f m x %.1f m: the busiest 1/%d of it holds %.1f %% of %.0f descriptor centres\n",
                e.width(), e.height(), kCols * kRows,
                100.0 * *std::max_element(cells.begin(), cells.end()) / std::max(total, 1.0), total);
    return 0;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "part_stats: error: %s\n", ex.what());
    return 1;
  }
}
