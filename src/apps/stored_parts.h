// Shared by `partslam describe`, `match` and `render`: the stored descriptors of one dictionary, decoded with
// the codec that core/parts/descriptor_layout.h derives from the dictionary's points and K.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "core/parts/cpd.h"
#include "core/parts/part.h"
#include "io/map_database.h"

namespace partslam::apps {

/// The CPD parameters as options of `cmd`, each named --PREFIXNAME (prefix "" for describe and render,
/// "cpd-" for eval and demo): candidates, partitions, corners, box-sizes, corner-radius,
/// corner-spacing, mc, tsize, gc, seed, dilation (of the crop-vs-dictionary fit, Eq. 2).
void add_cpd_options(CLI::App& cmd, CpdConfig& cpd, const std::string& prefix);

/// The dictionary named, or when name is empty the only dictionary of the database; throws InputError naming
/// what is missing or ambiguous.
io::Dictionary resolve_dictionary(const io::MapDatabase& db, const std::string& name);

/// "run 'partslam describe DB --dict NAME --k K'": how to produce a missing descriptor set.
std::string describe_hint(const io::MapDatabase& db, const std::string& dictionary, int k);

/// Every stored descriptor of (dictionary, K), decoded, by map id.
std::map<std::int64_t, MapDescriptor> load_descriptor_set(const io::MapDatabase& db,
                                                          const io::Dictionary& dictionary, int k);

/// One map's stored descriptor of (dictionary, K), decoded; nullopt when there is none.
std::optional<MapDescriptor> load_descriptor(const io::MapDatabase& db, const io::Dictionary& dictionary,
                                             int k, std::int64_t map_id);

/// K of the longest hMM query list (K > kMaxUnscoredParts, appearance scores stored) kept for the dictionary
/// that holds map_id; 0 when there is none.
int query_list_parts(const io::MapDatabase& db, const std::string& dictionary, std::int64_t map_id);

}  // namespace partslam::apps
