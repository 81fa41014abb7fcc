#include "core/evaluation/trajectory_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/testing/scan_index.h"

namespace partslam {
namespace {

// A straight drive along x, one scan every 0.1 m, each seeing one point 2 m to its left.
Scans straight(int n) {
  Scans scans(n);
  for (int i = 0; i < n; ++i) {
    scans[i].timestamp = i;
    scans[i].T_world_laser = {0.1 * i, 0.0, 0.0};
    scans[i].points_laser = {{0.0, 2.0}};
  }
  return scans;
}

TEST(LocalConsistency, IsZeroForTheSameTrajectoryAndIgnoresAGlobalOffset) {
  const Scans ref = straight(50);
  Scans moved = ref;
  for (Scan& s : moved) s.T_world_laser = Pose2{3.0, -1.0, 0.7} * s.T_world_laser;  // anchors absorb it
  const Consistency c = local_consistency(moved, ref, testing::identity_index(ref.size()));
  EXPECT_EQ(c.windows, 10u);  // anchors every 0.5 m over 4.9 m
  EXPECT_GT(c.points, 0u);
  EXPECT_NEAR(c.max, 0.0, 1e-9);
}

TEST(LocalConsistency, MeasuresTheEndpointDisplacementOfARelativePoseError) {
  const Scans ref = straight(50);
  Scans est = ref;
  est[25].T_world_laser.y += 0.05;  // one scan off by 5 cm sideways
  const Consistency c = local_consistency(est, ref, testing::identity_index(ref.size()));
  EXPECT_NEAR(c.max, 0.05, 1e-9);
  EXPECT_NEAR(c.median, 0.0, 1e-9);
  // Scans missing from the reference are skipped, anchors too.
  auto index = testing::identity_index(ref.size());
  index[25].reset();
  index[0].reset();
  const Consistency skipped = local_consistency(est, ref, index);
  EXPECT_NEAR(skipped.max, 0.0, 1e-9);
  EXPECT_LT(skipped.windows, c.windows);  // anchors without a reference are skipped
  EXPECT_THROW(local_consistency(est, ref, {}), InputError);
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST(ReferenceFrames, CarryEachSubmapIntoTheReferenceFrame) {
  const Scans ref = straight(30);
  const Pose2 drift{1.0, -2.0, 0.3};
  Scans est = ref;
  for (Scan& s : est) s.T_world_laser = drift * s.T_world_laser;
  Submap m;
  m.anchor_scan = 10;
  m.scan_timestamps.assign(5, 0.0);  // scans 10..14
  const Pose2 T_anchor_map{0.5, 0.2, 0.1};
  m.T_world_map = est[10].T_world_laser * T_anchor_map;
  Submap far = m;
  far.anchor_scan = 20;
  auto index = testing::identity_index(est.size());
  index[10].reset();  // the next scan of the submap stands in for its anchor
  for (std::size_t j = 20; j < 25; ++j) index[j].reset();
  const auto frames = reference_frames({m, far}, est, ref, index);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_FALSE(frames[1].has_value());
  const Submaps out = with_reference_frames({m, far}, frames);
  ASSERT_EQ(out.size(), 1u);
  const Pose2 expected = ref[10].T_world_laser * T_anchor_map;
  EXPECT_NEAR(out[0].T_world_map.x, expected.x, 1e-9);
  EXPECT_NEAR(out[0].T_world_map.y, expected.y, 1e-9);
  EXPECT_NEAR(out[0].T_world_map.theta, expected.theta, 1e-9);
  EXPECT_THROW(reference_frames({m}, est, ref, {}), InputError);
  EXPECT_THROW(with_reference_frames({m}, {}), InputError);
}

// A scan whose estimated pose is off from the rest of its submap (a front end that lost one scan's heading in a
// fast turn, as intel's raw log does at scan 5392) does not stand for the submap: the frame most of its
// referenced scans agree with does. Two that disagree leave the submap without a true frame.
TEST(ReferenceFrames, FollowTheFrameMostOfTheSubmapsScansAgreeOn) {
  const Scans ref = straight(30);
  Scans est = ref;
  const Pose2 spike{0.0, 0.0, 0.3};
  est[10].T_world_laser = est[10].T_world_laser * spike;  // the submap's first scan, off by 0.3 rad
  Submap m;
  m.anchor_scan = 10;
  m.scan_timestamps.assign(5, 0.0);  // scans 10..14
  m.T_world_map = est[12].T_world_laser * Pose2{0.5, 0.2, 0.1};
  const auto index = testing::identity_index(est.size());
  const auto frames = reference_frames({m}, est, ref, index);
  ASSERT_TRUE(frames[0].has_value());
  const Pose2 expected = ref[12].T_world_laser * (est[12].T_world_laser.inverse() * m.T_world_map);
  EXPECT_NEAR(frames[0]->x, expected.x, 1e-9);
  EXPECT_NEAR(frames[0]->y, expected.y, 1e-9);
  EXPECT_NEAR(frames[0]->theta, expected.theta, 1e-9);
  // The first scan alone (what the frame was before) is 0.3 rad off.
  const Pose2 first = ref[10].T_world_laser * (est[10].T_world_laser.inverse() * m.T_world_map);
  EXPECT_GT(std::abs(wrap_angle(first.theta - expected.theta)), 0.29);
  // Only scans 10 and 12 have a reference: one against one, no true frame.
  auto two = index;
  for (const std::size_t j : {11, 13, 14}) two[j].reset();
  EXPECT_FALSE(reference_frames({m}, est, ref, two)[0].has_value());
  // Within the agreement tolerance they are one frame again.
  EXPECT_TRUE(reference_frames({m}, est, ref, two, {0.25, 0.35})[0].has_value());
}

}  // namespace
}  // namespace partslam

namespace partslam {
namespace {

TEST(RelationsError, IsZeroForTheTrueTrajectoryAndMeasuresAnOffset) {
  const Scans ref = straight(20);
  Relations relations = {{ref[2].timestamp, ref[12].timestamp, ref[2].T_world_laser.inverse() * ref[12].T_world_laser},
                         {ref[3].timestamp, 99.0, Pose2{}}};  // the second names a scan that is not there
  RelationsError e = relations_error(ref, relations);
  EXPECT_EQ(e.relations, 1u);
  EXPECT_EQ(e.missing, 1u);
  EXPECT_NEAR(e.translation_mean, 0.0, 1e-12);
  Scans est = ref;
  est[12].T_world_laser.y += 0.3;
  est[12].T_world_laser.theta += 0.1;
  e = relations_error(est, relations);
  EXPECT_NEAR(e.translation_mean, 0.3, 1e-9);
  EXPECT_NEAR(e.rotation_mean, 0.1, 1e-9);
  EXPECT_NEAR(e.translation_std, 0.0, 1e-12);
}

// Relations of robot poses (as the Freiburg hospital's are). With the laser 0.22 m ahead of the robot's origin (that
// hospital's bag), a U-turn moves the laser 0.44 m more than the robot: measured on the laser's poses, a perfect
// trajectory would be 0.44 m off; with the mount taken off, 0.
TEST(RelationsError, RelatesRobotPosesWhenTheLaserIsMountedOffTheOrigin) {
  const Pose2 mount{0.22, 0.0, 0.0};
  Scans scans = straight(4);
  const std::vector<Pose2> robot = {{0, 0, 0}, {1, 0, 0}, {1, 0, std::numbers::pi / 2}, {1, 0, std::numbers::pi}};
  for (std::size_t i = 0; i < 4; ++i) scans[i].T_world_laser = robot[i] * mount;
  const Relations relations = {{scans[0].timestamp, scans[3].timestamp, robot[0].inverse() * robot[3]},
                               {scans[1].timestamp, scans[2].timestamp, robot[1].inverse() * robot[2]}};
  const RelationsError on_robot = relations_error(scans, relations, mount);
  EXPECT_EQ(on_robot.relations, 2u);
  EXPECT_NEAR(on_robot.translation_mean, 0.0, 1e-12);
  const RelationsError on_laser = relations_error(scans, relations);
  EXPECT_NEAR(on_laser.translation_mean, (0.44 + 0.22 * std::sqrt(2.0)) / 2, 1e-9);
  EXPECT_NEAR(on_laser.rotation_mean, 0.0, 1e-12);
}

TEST(RelationsError, NamesTheScanOfNearestTimestampNotTheFirstWithinAMillisecond) {
  Scans scans = straight(20);
  scans[12].timestamp = 11.9996;  // a neighbour 0.4 ms before the named scan (intel has 1479 such pairs)
  scans[12].T_world_laser.x += 5.0;
  scans[13].timestamp = 12.0;
  const Pose2 truth = scans[2].T_world_laser.inverse() * scans[13].T_world_laser;
  RelationsError e = relations_error(scans, {{scans[2].timestamp, 12.0, truth}});
  EXPECT_EQ(e.relations, 1u);
  EXPECT_NEAR(e.translation_mean, 0.0, 1e-12);  // the first scan within 1 ms would be 5 m off
  e = relations_error(scans, {{scans[2].timestamp, 12.0015, truth}});  // nothing within 1 ms
  EXPECT_EQ(e.relations, 0u);
  EXPECT_EQ(e.missing, 1u);
}

}  // namespace
}  // namespace partslam
