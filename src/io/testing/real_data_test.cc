// Real-data tests of the log and relations readers on every log in the shared data folder (skipped
// when it is absent): known scan / ODOM counts, plausible scans, relation timestamps and frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "io/logs/carmen_log.h"
#include "io/logs/no_return_codes.h"
#include "io/logs/relations.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

struct LogFacts {
  std::size_t scans;
  std::size_t odometry;
  double code = 0.0;  ///< the scanner's no-return code below 81 m, 0 if none: the 1 cm value most frequent beyond 30 m
};

// Counted independently with zcat | awk (the codes: a histogram of the ranges beyond 30 m, by /usr/bin/python3).
const std::map<std::string, LogFacts> kLogs = {
    {"aces/aces-corrected.log.gz", {440, 7814, 50.0}},
    {"aces/aces.clf.gz", {7374, 7375, 50.0}},
    {"corrected/acapulco-corrected.log.gz", {861, 12142, 51.15}},
    {"corrected/belgioioso-corrected.log.gz", {395, 4442}},
    {"corrected/edmonton-corrected.log.gz", {340, 6351, 51.15}},
    {"corrected/fhw-corrected.log.gz", {488, 13935, 51.05}},
    {"corrected/freiburg-campus-corrected.log.gz", {2008, 17691}},
    {"corrected/infinite-corridor-corrected.log.gz", {1941, 18191, 51.06}},
    {"corrected/orebro-corrected.log.gz", {237, 255, 32.76}},
    {"corrected/seattle-corrected.log.gz", {241, 19311}},
    {"csail/mit-csail.clf.gz", {1988, 0}},  // FLASER only: the pose fields carry the odometry
    {"fr079/fr079-corrected.log.gz", {4791, 9725}},
    {"fr079/fr079.clf.gz", {4934, 8951}},
    {"fr101/fr101-corrected.log.gz", {292, 4569}},
    {"fr101/fr101.clf.gz", {4758, 8955}},
    {"intel/intel-corrected.log.gz", {910, 14541}},
    {"intel/intel-robotlaser.log.gz", {2672, 0}},  // ROBOTLASER1 only
    {"intel/intel.clf.gz", {13631, 26915}},
};

#define SKIP_WITHOUT_DATA()                                                            \
  if (!std::filesystem::is_directory(testing::shared_data())) {                        \
    GTEST_SKIP() << "shared data folder " << testing::shared_data()                    \
                 << " is absent; set PARTSLAM_SHARED_DATA to run the real-data tests"; \
  }

/// Median over scan pairs (i, i + step) of the median distance from scan i+step's world points to
/// the nearest world point of scan i: small only if poses, beam angles and their sign are right.
double median_overlap_distance(const Scans& scans, std::size_t step, bool mirror) {
  std::vector<double> medians;
  for (std::size_t i = 0; i + step < scans.size(); i += 25) {
    Scan a = scans[i], b = scans[i + step];
    if (mirror) {
      for (Scan* s : {&a, &b}) {
        for (Vec2& p : s->points_laser) p.y() = -p.y();
      }
    }
    const Points2 pa = points_world(a), pb = points_world(b);
    if (pa.size() < 20 || pb.size() < 20) continue;
    std::vector<double> d;
    for (const Vec2& p : pb) {
      double best = 1e18;
      for (const Vec2& q : pa) best = std::min(best, (p - q).squaredNorm());
      d.push_back(std::sqrt(best));
    }
    std::nth_element(d.begin(), d.begin() + static_cast<long>(d.size() / 2), d.end());
    medians.push_back(d[d.size() / 2]);
  }
  std::nth_element(medians.begin(), medians.begin() + static_cast<long>(medians.size() / 2), medians.end());
  return medians[medians.size() / 2];
}

TEST(RealData, EveryLogIsKnown) {
  SKIP_WITHOUT_DATA();
  std::size_t found = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(testing::shared_data())) {
    const std::string name = entry.path().filename().string();
    if (!name.ends_with(".clf.gz") && !name.ends_with(".log.gz")) continue;
    const std::string rel = std::filesystem::relative(entry.path(), testing::shared_data()).string();
    EXPECT_TRUE(kLogs.contains(rel)) << rel << " has no expected counts in kLogs";
    ++found;
  }
  EXPECT_EQ(found, kLogs.size());
}

class RealLog : public ::testing::TestWithParam<std::string> {};

TEST_P(RealLog, ParsesWithKnownCountsAndPlausibleScans) {
  SKIP_WITHOUT_DATA();
  const LogFacts facts = kLogs.at(GetParam());
  const CarmenLog log = read_carmen_log(testing::shared_data() / GetParam());
  EXPECT_EQ(log.scans.size(), facts.scans);
  EXPECT_EQ(log.odometry.size(), facts.odometry);
  std::size_t sparse = 0;
  for (const Scan& scan : log.scans) {
    const int n = scan.num_beams;
    ASSERT_TRUE(n == 180 || n == 181 || n == 360 || n == 361) << n;
    ASSERT_LE(scan.points_laser.size(), static_cast<std::size_t>(n));
    ASSERT_TRUE(std::isfinite(scan.T_world_laser.x) && std::isfinite(scan.T_world_odom.theta));
    for (const Vec2& p : scan.points_laser) {
      ASSERT_LT(p.norm(), LogReadOptions{}.max_usable_range);
      ASSERT_GT(std::abs(p.norm() - facts.code), kNoReturnCodeWindow) << "a no-return code kept";
    }
    if (scan.points_laser.size() < static_cast<std::size_t>(n) / 4) ++sparse;
  }
  EXPECT_EQ(log.stats.no_return_code_beams > 0, facts.code > 0);
  EXPECT_TRUE(find_no_return_codes(log.scans, LogReadOptions{}).empty());
  // Outdoor freiburg-campus is the worst: 6 % sparse scans, 74 % valid beams (62 % within 30 m).
  EXPECT_LT(sparse, log.scans.size() / 10) << "scans with under a quarter of their beams valid";
  EXPECT_GT(log.stats.valid_beams, log.stats.beams / 2);
}

INSTANTIATE_TEST_SUITE_P(AllLogs, RealLog, ::testing::ValuesIn([] {
                           std::vector<std::string> names;
                           for (const auto& [name, facts] : kLogs) names.push_back(name);
                           return names;
                         }()),
                         [](const auto& info) {
                           std::string name = info.param.substr(info.param.find('/') + 1);
                           name = name.substr(0, name.find('.'));
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(RealData, ConsecutiveCorrectedScansOverlap) {
  SKIP_WITHOUT_DATA();
  for (const char* name : {"fr079/fr079-corrected.log.gz", "intel/intel-robotlaser.log.gz"}) {
    const Scans scans = read_carmen_log(testing::shared_data() / name).scans;
    const double aligned = median_overlap_distance(scans, 5, false);
    const double mirrored = median_overlap_distance(scans, 5, true);
    EXPECT_LT(aligned, 0.05) << name;
    EXPECT_GT(mirrored, 2.0 * aligned) << name << ": the overlap test must notice mirrored beam angles";
  }
}

TEST(RealData, RelationsMatchRawScansAndOdometry) {
  SKIP_WITHOUT_DATA();
  const std::map<std::string, std::size_t> kRelations = {{"fr079", 1685}, {"intel", 2984}, {"aces", 1279}};
  for (const auto& [name, count] : kRelations) {
    const auto folder = testing::shared_data() / name;
    const Relations relations = read_relations(folder / (name + ".relations"));
    EXPECT_EQ(relations.size(), count) << name;
    const Scans scans = read_carmen_log(folder / (name + ".clf.gz")).scans;
    std::vector<double> errors;  // |odometry motion - relation| over relations spanning < 2 s
    for (const Relation& r : relations) {
      const auto i = find_scan_by_timestamp(scans, r.t1, 1e-5);
      const auto j = find_scan_by_timestamp(scans, r.t2, 1e-5);
      ASSERT_TRUE(i && j) << name << ": no scan at " << r.t1 << " or " << r.t2;
      if (std::abs(r.t2 - r.t1) > 2.0) continue;
      const Pose2 odo = scans[*i].T_world_odom.inverse() * scans[*j].T_world_odom;
      errors.push_back(std::hypot(odo.x - r.T_1_2.x, odo.y - r.T_1_2.y));
    }
    ASSERT_GT(errors.size(), 100u) << name;
    std::nth_element(errors.begin(), errors.begin() + static_cast<long>(errors.size() / 2), errors.end());
    EXPECT_LT(errors[errors.size() / 2], 0.05) << name << ": relations are T_1_2 = T_world_1^-1 * T_world_2";
  }
}

}  // namespace
}  // namespace partslam::io
