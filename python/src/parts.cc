// Python bindings of the paper's parts (core/parts) and the dictionary map they are described against
// (core/maps/dictionary.h): building a dictionary, common pattern discovery (CPD, Eq. 2), the top-K
// selection, the bit-packed codec and the layout a database stores descriptors under, and the descriptor
// matcher's scores (Eqs. 3-6). A map descriptor is a list of Part, best first. Dictionary building and CPD
// release the GIL.
#include "casters.h"
// (casters.h first: see its header comment)
#include <array>

#include "bindings.h"
#include "core/maps/dictionary.h"
#include "core/parts/cpd.h"
#include "core/parts/descriptor_layout.h"
#include "core/parts/descriptor_matcher.h"
#include "core/parts/part.h"
#include "core/parts/part_codec.h"

namespace partslam::python {

namespace py = pybind11;
using namespace pybind11::literals;
using release_gil = py::call_guard<py::gil_scoped_release>;

namespace {

Vec2 to_vec(const std::array<double, 2>& xy) { return {xy[0], xy[1]}; }

void define_part(py::module_& m) {
  py::class_<Part> part(
      m, "Part",
      "A part: a keypoint box on the map and the descriptor box where its points fit the "
      "dictionary, rotated by `rotation` quarter turns; boxes are (x_min, x_max, y_min, y_max) [m].");
  part.def_readwrite("keypoint_box", &Part::keypoint_box, "on the map, in its canonical frame")
      .def_readwrite("descriptor_box", &Part::descriptor_box, "on the dictionary, in its frame")
      .def_readwrite("appearance_score", &Part::appearance_score, "AS (Eq. 2): inlier fraction of the crop")
      .def_readwrite("rotation", &Part::rotation, "quarter turns k in {0, 1, 2, 3} of T_dict_map")
      .def("__repr__", [](const Part& p) {
        const py::str text =
            py::str("<partslam.Part keypoint_box={} descriptor_box={} AS={:.3f} rotation={}>");
        return text.format(p.keypoint_box, p.descriptor_box, p.appearance_score, p.rotation);
      });
  def_keyword_init(part);

  m.def(
      "select_top_parts",
      [](std::vector<Part> parts, int k) { return select_top_parts(std::move(parts), k).parts; }, "parts"_a,
      "k"_a, "MD: the K parts of highest appearance score, best first (ties keep their order).");
  m.def(
      "place_rotated_box",
      [](const Box2& keypoint_box, int rotation, const std::array<double, 2>& origin) {
        return place_rotated_box(keypoint_box, rotation, to_vec(origin));
      },
      "keypoint_box"_a, "rotation"_a, "origin"_a,
      "The box keypoint_box occupies after `rotation` quarter turns, its minimum corner at origin (x, y).");
  m.def(
      "dictionary_origin", [](const Part& p) { return to_tuple(dictionary_origin(p)); }, "part"_a,
      "Where the part puts its map's frame origin on the dictionary (x, y) [m].");
}

void define_codec(py::module_& m) {
  py::class_<CodecConfig> config(m, "CodecConfig",
                                 "The bit layout of packed descriptors (core/parts/part_codec.h)");
  config.def_readwrite("crop_size", &CodecConfig::crop_size, "[m]")
      .def_readwrite("keypoint_resolution", &CodecConfig::keypoint_resolution, "[m]")
      .def_readwrite("keypoint_bits", &CodecConfig::keypoint_bits)
      .def_readwrite("dictionary_extent", &CodecConfig::dictionary_extent,
                     "box of the dictionary frame the descriptor origins lie in [m]; required")
      .def_readwrite("origin_bits_x", &CodecConfig::origin_bits_x)
      .def_readwrite("origin_bits_y", &CodecConfig::origin_bits_y)
      .def_readwrite("rotation_bits", &CodecConfig::rotation_bits, "0, 1 or 2")
      .def_readwrite("score_bits", &CodecConfig::score_bits, "0..16 (0: the appearance score is not stored)")
      .def_readwrite("score_max", &CodecConfig::score_max)
      .def("validate", py::overload_cast<const CodecConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(config);

  py::class_<PackedDescriptor>(m, "PackedDescriptor", "A packed descriptor: `bits` meaningful bits in `data`")
      .def(py::init([](const py::bytes& data, int bits) {
             const std::string text = data;
             return PackedDescriptor{std::vector<std::uint8_t>(text.begin(), text.end()), bits};
           }),
           "data"_a, "bits"_a)
      .def_property_readonly("data",
                             [](const PackedDescriptor& d) {
                               return py::bytes(reinterpret_cast<const char*>(d.bytes.data()),
                                                d.bytes.size());
                             })
      .def_readonly("bits", &PackedDescriptor::bits)
      .def("__repr__", [](const PackedDescriptor& d) {
        return "<partslam.PackedDescriptor bits=" + std::to_string(d.bits) + ">";
      });

  m.def("bits_per_part", &bits_per_part, "codec"_a, "Bits one part costs.");
  m.def("packed_bits", &packed_bits, "num_parts"_a, "codec"_a, "Bits of a descriptor of num_parts parts.");
  m.def(
      "origin_step", [](const CodecConfig& c) { return to_tuple(origin_step(c)); }, "codec"_a,
      "Lattice step of the descriptor origin (x, y) [m].");
  m.def(
      "encode",
      [](std::vector<Part> parts, const CodecConfig& codec) { return encode({std::move(parts)}, codec); },
      "parts"_a, "codec"_a, "Packs a descriptor (list of Part).");
  m.def(
      "decode",
      [](const PackedDescriptor& packed, const CodecConfig& codec) { return decode(packed, codec).parts; },
      "packed"_a, "codec"_a, "Unpacks a descriptor (list of Part), exact up to the codec's quantisation.");

  m.attr("MAX_UNSCORED_PARTS") = kMaxUnscoredParts;
  m.attr("QUERY_SCORE_BITS") = kQueryScoreBits;
  m.def("dictionary_codec_config", &dictionary_codec_config, "dictionary_points"_a, "base"_a = CodecConfig{},
        "`base` with the dictionary extent a database stores descriptors of this dictionary under.");
  m.def("score_bits_for_parts", &score_bits_for_parts, "k"_a,
        "Score bits of a descriptor stored under K parts.");
  m.def("descriptor_codec_config", &descriptor_codec_config, "dictionary_points"_a, "k"_a,
        "base"_a = CodecConfig{}, "The codec of a descriptor stored under K parts against this dictionary.");
  m.def(
      "decode_stored",
      [](const PackedDescriptor& packed, int k, const CodecConfig& codec) {
        return decode_stored(packed, k, codec).parts;
      },
      "packed"_a, "k"_a, "codec"_a, "Decodes a stored descriptor of up to K parts.");
}

void define_matcher(py::module_& m) {
  py::enum_<Matcher>(m, "Matcher", "The descriptor matcher's score (Eqs. 4-6)")
      .value("MAX_MAX", Matcher::kMaxMax)
      .value("SUM_MAX", Matcher::kSumMax)
      .value("SUM_MAX_WEIGHTED", Matcher::kSumMaxWeighted);
  m.def("matcher_from_string", &matcher_from_string, "name"_a,
        "'max-max', 'sum-max', 'sum-max-weighted' (or 'mm', 'sm', 'smw').");
  m.attr("DEFAULT_ORIGIN_GATE") = kDefaultOriginGate;
  m.def("region_similarity", &region_similarity, "a"_a, "b"_a, "f_RS (Eq. 3) of two boxes, in [0, 1].");
  m.def(
      "match_score",
      [](std::vector<Part> query, std::vector<Part> stored, Matcher matcher, double origin_gate) {
        return match_score({std::move(query)}, {std::move(stored)}, matcher, origin_gate);
      },
      "query_parts"_a, "stored_parts"_a, "matcher"_a = Matcher::kSumMax, "origin_gate"_a = 0.0,
      "F_MM, F_SM or F_SMW between a query and a stored descriptor; origin_gate 0 = the paper's matcher.");
  m.def(
      "passes_origin_gate", &passes_origin_gate, "query"_a, "stored"_a, "origin_gate"_a,
      "True when the two parts' dictionary origins are within origin_gate on both axes (or the gate is 0).");
}

void define_dictionary(py::module_& m) {
  py::class_<DictionaryConfig> config(m, "DictionaryConfig", "How a dictionary map is built");
  config.def_readwrite("resolution", &DictionaryConfig::resolution, "[m]")
      .def_readwrite("align", &DictionaryConfig::align)
      .def_readwrite("min_points", &DictionaryConfig::min_points)
      .def_readwrite("max_range", &DictionaryConfig::max_range, "[m]");
  def_keyword_init(config);

  py::class_<Dictionary> dictionary(
      m, "Dictionary", "A whole-building map of another dataset that parts are described against");
  dictionary.def_readwrite("name", &Dictionary::name)
      .def_readwrite("source", &Dictionary::source)
      .def_readwrite("resolution", &Dictionary::resolution, "[m]")
      .def_readwrite("alignment_angle", &Dictionary::alignment_angle, "[rad]")
      .def_readwrite("T_world_dict", &Dictionary::T_world_dict)
      .def_readwrite("points", &Dictionary::points, "(n, 2) array in the dictionary frame [m], a copy")
      .def_readwrite("metadata", &Dictionary::metadata, "JSON object")
      .def("__repr__", [](const Dictionary& d) {
        return "<partslam.Dictionary '" + d.name + "' points=" + std::to_string(d.points.size()) + ">";
      });
  def_keyword_init(dictionary);
  m.def("build_dictionary",
        py::overload_cast<const std::string&, const Scans&, const DictionaryConfig&>(&build_dictionary), "name"_a,
        "scans"_a, "config"_a = DictionaryConfig{}, release_gil(),
        "The dictionary map of a scan stream (every scan, one point per cell, Manhattan-aligned).");
  m.def("build_dictionary_from_points",
        py::overload_cast<const std::string&, const Points2&, const DictionaryConfig&>(&build_dictionary), "name"_a,
        "points"_a, "config"_a = DictionaryConfig{}, release_gil(),
        "The dictionary map of a building's points in its world frame (a map_server map's occupied cells).");
}

void define_cpd(py::module_& m) {
  py::enum_<MaximalityMode>(m, "MaximalityMode")
      .value("POINT_SHARE", MaximalityMode::kPointShare)
      .value("INLIER_SHARE", MaximalityMode::kInlierShare);
  py::enum_<CandidateMode>(m, "CandidateMode")
      .value("PARTITIONS", CandidateMode::kPartitions)
      .value("CORNERS", CandidateMode::kCorners);

  py::class_<CpdConfig> config(m, "CpdConfig", "Common pattern discovery (core/parts/cpd.h)");
  config.def_readwrite("max_parts", &CpdConfig::max_parts)
      .def_readwrite("candidates", &CpdConfig::candidates)
      .def_readwrite("partitions", &CpdConfig::partitions)
      .def_readwrite("min_cell_fraction", &CpdConfig::min_cell_fraction)
      .def_readwrite("max_cell_fraction", &CpdConfig::max_cell_fraction)
      .def_readwrite("maximality", &CpdConfig::maximality)
      .def_readwrite("t_size", &CpdConfig::t_size)
      .def_readwrite("min_crop_points", &CpdConfig::min_crop_points)
      .def_readwrite("geometric_consistency", &CpdConfig::geometric_consistency)
      .def_readwrite("corners", &CpdConfig::corners)
      .def_readwrite("box_sizes", &CpdConfig::box_sizes, "[m], a copy: assign a new list")
      .def_readwrite("corner_radius", &CpdConfig::corner_radius, "[m]")
      .def_readwrite("corner_spacing", &CpdConfig::corner_spacing, "[m]")
      .def_readwrite("crop_extent", &CpdConfig::crop_extent, "[m]")
      .def_readwrite("crop_resolution", &CpdConfig::crop_resolution, "[m]")
      .def_readwrite("seed", &CpdConfig::seed)
      .def_readwrite("dmm", &CpdConfig::dmm, "the crop-vs-dictionary search (Eq. 2)")
      .def("validate", py::overload_cast<const CpdConfig&>(&validate),
           "Raises InputError naming the field that is out of range.");
  def_keyword_init(config);

  py::class_<PreparedDictionary>(m, "PreparedDictionary", "A dictionary prepared once for CPD")
      .def_readonly("extent", &PreparedDictionary::extent, "bounding box of the dictionary points [m]")
      .def_property_readonly("num_points", [](const PreparedDictionary& d) { return d.map.num_points; });
  py::class_<CpdStats>(m, "CpdStats")
      .def_readonly("candidates", &CpdStats::candidates)
      .def_readonly("passed_mc", &CpdStats::passed_mc)
      .def_readonly("matched", &CpdStats::matched)
      .def_readonly("passed_gc", &CpdStats::passed_gc);
  py::class_<CpdResult>(m, "CpdResult")
      .def_readonly("parts", &CpdResult::parts, "best AS first")
      .def_readonly("stats", &CpdResult::stats)
      .def_readonly("ms", &CpdResult::ms, "wall time of this map's CPD [ms]");

  m.def("prepare_dictionary", &prepare_dictionary, "dictionary_points"_a, "config"_a = CpdConfig{},
        release_gil(), "Prepares the dictionary once for CPD.");
  m.def("find_corners", &find_corners, "points"_a, "config"_a = CpdConfig{}, release_gil(),
        "The map's corner points, strongest first (the CORNERS candidates' centres).");
  m.def("discover_parts", &discover_parts, "points"_a, "dictionary"_a, "config"_a = CpdConfig{},
        "map_key"_a = 0, release_gil(),
        "Parts of one map (points in its canonical frame); map_key (e.g. its id) seeds it.");
  m.def(
      "discover_parts_many",
      [](const std::vector<Points2>& maps, const std::vector<std::uint64_t>& map_keys,
         const PreparedDictionary& dictionary, const CpdConfig& config, int threads) {
        std::vector<const Points2*> pointers;
        for (const Points2& p : maps) pointers.push_back(&p);
        return discover_parts_many(pointers, map_keys, dictionary, config, threads);
      },
      "maps"_a, "map_keys"_a, "dictionary"_a, "config"_a = CpdConfig{}, "threads"_a = 1, release_gil(),
      "discover_parts over many maps, each seeded by its key; the same parts for any number of threads.");
}

}  // namespace

void define_parts(py::module_& m) {
  define_part(m);
  define_codec(m);
  define_matcher(m);
  define_dictionary(m);
  define_cpd(m);
}

}  // namespace partslam::python
