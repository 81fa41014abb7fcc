// front_end_check RAW_LOG CORRECTED_LOG [LINEAR_WINDOW ANGULAR_WINDOW]: how locally consistent is the
// scan-matched trajectory of a raw log? Runs the front end (core/slam/front_end.h) with its defaults (or the given search window),
// associates the raw scans with the corrected twin's by content, and prints the local consistency
// (core/evaluation/trajectory_check.h: median / p90 / max displacement of beam endpoints within 8 m inside
// 2 m submap windows) of the raw odometry and of the front end, the front end's time and its factor over the
// log's real time.
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "core/evaluation/relation_check.h"
#include "core/evaluation/trajectory_check.h"
#include "core/slam/front_end.h"
#include "io/logs/scan_source.h"

using namespace partslam;

int main(int argc, char** argv) {
  if (argc != 3 && argc != 5) {
    std::fprintf(stderr, "usage: front_end_check RAW_LOG CORRECTED_LOG [LINEAR_WINDOW ANGULAR_WINDOW]\n");
    return 2;
  }
  try {
    const Scans raw = io::load_scan_source(argv[1]).scans;
    const Scans corrected = io::load_scan_source(argv[2]).scans;
    FrontEndConfig config;
    if (argc == 5) config.matcher.linear_window = std::atof(argv[3]), config.matcher.angular_window = std::atof(argv[4]);
    const FrontEndResult fe = scan_match_log(raw, config);
    const auto index = associate_scans(fe.scans, corrected);
    std::size_t associated = 0;
    for (const auto& i : index) associated += i.has_value();
    Scans odometry = fe.scans;
    for (Scan& s : odometry) s.T_world_laser = s.T_world_odom;
    const Consistency before = local_consistency(odometry, corrected, index);
    const Consistency after = local_consistency(fe.scans, corrected, index);
    const FrontEndStats& st = fe.stats;
    std::printf("%s: %zu scans (%zu associated with %s), %zu rejected matches, %zu time reversals, mean score %.3f\n",
                argv[1], st.scans, associated, argv[2], st.rejected, st.time_reversals, st.mean_score);
    std::printf("front end: %.1f s for %.0f s of log (%.0fx real time)\n", st.seconds, st.log_seconds,
                st.log_seconds / st.seconds);
    for (const auto& [name, c] : {std::pair{"odometry", before}, std::pair{"front end", after}}) {
      std::printf("%-10s %zu windows, %zu points: median %.1f cm, p90 %.1f cm, max %.1f cm\n", name, c.windows,
                  c.points, 100 * c.median, 100 * c.p90, 100 * c.max);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "front_end_check: %s\n", e.what());
    return 1;
  }
  return 0;
}
