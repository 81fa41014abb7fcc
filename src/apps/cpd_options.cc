#include "apps/cpd_options.h"

#include <sstream>

#include "core/error.h"

namespace partslam::apps {

namespace {

// An option that takes one of a few names and sets `target` to the value named; anything else is an
// InputError naming the flag and the choices.
template <class Enum>
void add_choice(CLI::App& cmd, const std::string& flag, Enum& target,
                const std::vector<std::pair<std::string, Enum>>& choices, const std::string& help) {
  std::string names, current;
  for (const auto& [name, value] : choices) {
    names += (names.empty() ? "" : " or ") + name;
    if (value == target) current = name;
  }
  cmd.add_option_function<std::string>(
         flag,
         [&target, flag, choices, names](const std::string& v) {
           for (const auto& [name, value] : choices)
             if (v == name) return void(target = value);
           throw InputError(flag + ": expected " + names + ", got '" + v + "'");
         },
         help)
      ->default_str(current);
}

}  // namespace

void add_cpd_options(CLI::App& cmd, CpdConfig& cpd, const std::string& prefix) {
  const auto name = [&prefix](const char* n) { return "--" + prefix + n; };
  add_choice(cmd, name("candidates"), cpd.candidates,
             {{"partitions", CandidateMode::kPartitions}, {"corners", CandidateMode::kCorners}},
             "CPD: candidate keypoint boxes, partitions (random grids, the paper) or corners (squares on corner "
             "points)");
  cmd.add_option(name("partitions"), cpd.partitions, "CPD: random partitions per map (candidates partitions)")
      ->capture_default_str()
      ->check(in_range(1, 100000));
  cmd.add_option(name("corners"), cpd.corners, "CPD: corner points per map (candidates corners)")
      ->capture_default_str()
      ->check(in_range(1, 10000));
  cmd.add_option(name("box-sizes"), cpd.box_sizes, "CPD: square sides on each corner [m], comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(in_range(0.2, 100.0));
  cmd.add_option(name("corner-radius"), cpd.corner_radius, "CPD: neighbourhood of the corner response [m]")
      ->capture_default_str()
      ->check(in_range(0.1, 10.0));
  cmd.add_option(name("corner-spacing"), cpd.corner_spacing,
                 "CPD: kept corners are at least this far apart [m]")
      ->capture_default_str()
      ->check(in_range(0.0, 100.0));
  add_choice(cmd, name("mc"), cpd.maximality,
             {{"point", MaximalityMode::kPointShare}, {"inlier", MaximalityMode::kInlierShare}},
             "CPD: MC reading, point (share of the map's points in the crop) or inlier (share of the crop's "
             "points that fit the dictionary)");
  cmd.add_option(name("tsize"), cpd.t_size, "CPD: MC threshold T^size")
      ->capture_default_str()
      ->check(in_range(0.0, 1.0));
  cmd.add_option(name("gc"), cpd.geometric_consistency,
                 "CPD: GC, keep only parts whose descriptor boxes pairwise overlap (true/false)")
      ->capture_default_str();
  cmd.add_option(name("seed"), cpd.seed, "CPD: base seed (mixed with each map id)")
      ->capture_default_str()
      ->check(non_negative_seed());
  cmd.add_option(name("dilation"), cpd.dmm.dilation,
                 "CPD: dilation of the dictionary's cells in the fit of a crop (Eq. 2) [cells]")
      ->capture_default_str();
}

const CLI::Validator& non_negative_seed() {
  static const CLI::Validator validator(
      [](std::string& v) { return !v.empty() && v.front() == '-' ? "must not be negative, got " + v : std::string(); },
      "SEED >= 0");
  return validator;
}

CLI::Validator in_range(double lo, double hi) {
  const auto text = [](double v) {
    std::ostringstream out;
    out << v;
    return out.str();
  };
  const std::string range = "[" + text(lo) + "," + text(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& v) {
        double x = 0;
        if (!CLI::detail::lexical_cast(v, x)) return "expected a number, got '" + v + "'";
        return x >= lo && x <= hi ? std::string() : "must be in " + range + ", got " + v;  // NaN is outside
      },
      range);
}

}  // namespace partslam::apps
