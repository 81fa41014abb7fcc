// CLI tests of the outside-world entry points: export-map, locate, match --query-points.
#include <cairo.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "apps/cli_testing.h"
#include "core/maps/submap.h"
#include "io/formats/point_export.h"
#include "io/logs/scan_source.h"
#include "plot/answer_image.h"

namespace partslam {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using ::testing::HasSubstr;
using testing::kNarrowDmm;
using testing::quoted;
using testing::run_partslam;

class CliLocateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("partslam_cli_locate_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
  nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
  }
  fs::path dir_;
};

// How many pixels of a PNG have exactly this colour; -1 when it is not a readable PNG.
long pixels_of(const fs::path& png, const plot::Rgb& c) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  long n = -1;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    const auto byte = [](double v) { return static_cast<std::uint32_t>(std::lround(v * 255)); };
    const std::uint32_t want = byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
    const unsigned char* data = cairo_image_surface_get_data(s);
    n = 0;
    for (int y = 0; y < cairo_image_surface_get_height(s); ++y)
      for (int x = 0; x < cairo_image_surface_get_width(s); ++x)
        n += (reinterpret_cast<const std::uint32_t*>(data + y * cairo_image_surface_get_stride(s))[x] & 0xFFFFFFu) ==
             want;
  }
  cairo_surface_destroy(s);
  return n;
}

// A picture of every answer: export-map's preview, locate's points on the map (confident: green) and its
// trajectory, match's best stored maps with the query on them.
TEST_F(CliLocateTest, PicturesOfEveryAnswer) {
  const fs::path yaml = dir_ / "building.yaml", db = dir_ / "maps.db";
  CliRun run = run_partslam("export-map sim:1 --out " + quoted(yaml));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("building.png (preview)"));
  EXPECT_GT(pixels_of(dir_ / "building.png", {0, 0, 0}), 100);  // walls
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --from 30 --to 32 --plot " +
                     quoted(dir_ / "one.png"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GT(pixels_of(dir_ / "one.png", plot::kGood), 100);
  EXPECT_EQ(pixels_of(dir_ / "one.png", plot::kDoubtful), 0);
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --every 40 --quiet --plot " +
                     quoted(dir_ / "every.png"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GT(pixels_of(dir_ / "every.png", plot::kGood), 20);
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db) + " --quiet").exit_code, 0);
  run = run_partslam("match " + quoted(db) + " --query-log sim:1 --from 30 --to 32 --plot " + quoted(dir_ / "m.png"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GT(pixels_of(dir_ / "m.png", plot::kMapGrey) + pixels_of(dir_ / "m.png", plot::kGood), 100);
  // An unwritable picture is refused before any work.
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --from 30 --to 32 --plot " +
                     quoted(dir_ / "no" / "such" / "dir.png"));
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("dir.png"));
}

// Options a new user got wrong are refused naming the option, before any long work.
TEST_F(CliLocateTest, AbsurdStretchesAndOptionsAreRefused) {
  const fs::path yaml = dir_ / "building.yaml", db = dir_ / "maps.db";
  ASSERT_EQ(run_partslam("export-map sim:1 --out " + quoted(yaml)).exit_code, 0);
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db) + " --quiet").exit_code, 0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"export-map sim:1 --out " + quoted(dir_ / "u.yaml") + " --until nan", "--until must be a finite travel >= 0"},
      {"export-map sim:1 --out " + quoted(dir_ / "u.yaml") + " --until -5", "--until must be a finite travel >= 0"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --at -5", "lies before the log's first scan"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --every 1e-9", "local maps along"},
      {"match " + quoted(db) + " --query 3 --from-m 1 --to-m 3", "go with --query-log, not --query ID"},
      {"locate --map " + quoted(dir_) + " --query-log sim:1 --at-m 3", "a folder, not a map YAML file"},
      {"submaps sim:1 --db " + quoted(dir_ / "t.db") + " --scan-topic /scan", "this is not a bag"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun run = run_partslam(args);
    EXPECT_EQ(run.exit_code, 1) << args << "\n" << run.output;
    EXPECT_THAT(run.output, HasSubstr(message)) << args;
  }
}

// The round trip a user makes: the simulated building's map exported as map_server files, then a stretch of the
// same log located in it: the robot's pose is the log's own (the map frame is the log's world frame).
TEST_F(CliLocateTest, ExportMapThenLocateAStretchOfTheLog) {
  const fs::path yaml = dir_ / "building.yaml", json = dir_ / "located.json";
  CliRun run = run_partslam("export-map sim:1 --out " + quoted(yaml));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(dir_ / "building.pgm"));
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --from 30 --to 32 --json " + quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("robot in the map"));
  const Scans scans = io::load_scan_source("sim:1").scans;
  const std::vector<double> s = travel_distances(scans);
  std::size_t first = 0;
  while (s[first] < 30) ++first;
  const Pose2 truth = scans[first].T_world_laser;
  const nlohmann::json j = read_json(json);
  ASSERT_EQ(j["located"].size(), 1u);
  const nlohmann::json& robot = j["located"][0]["robot_pose"];
  EXPECT_NEAR(robot["x"].get<double>(), truth.x, 0.3);
  EXPECT_NEAR(robot["y"].get<double>(), truth.y, 0.3);
  EXPECT_NEAR(wrap_angle(robot["theta"].get<double>() - truth.theta), 0.0, 0.05);
  EXPECT_GT(j["located"][0]["confidence"].get<double>(), 0.0);
  // Every term the probability reads, in [0, 1]; at the right place most of the query lies on the map.
  const nlohmann::json& terms = j["located"][0]["terms"];
  for (const char* term :
       {"query_occupied", "query_free", "query_seen", "map_occupied", "map_free", "map_seen", "query_fit",
        "map_fit", "query_corner", "map_corner", "query_corner_fit", "map_corner_fit"}) {
    ASSERT_TRUE(terms.contains(term)) << term;
    EXPECT_GE(terms[term].get<double>(), 0.0) << term;
    EXPECT_LE(terms[term].get<double>(), 1.0) << term;
  }
  EXPECT_GT(terms["query_corner"].get<double>(), 0.5);
  // --every sweeps the log; --until keeps the first scans only.
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --every 40 --quiet --json " + quoted(json) +
                     " --plot " + quoted(dir_ / "every.png"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("local maps,"));
  EXPECT_TRUE(fs::exists(dir_ / "every.png"));
  // An answer that is not confident says which test it failed, on its line and in the JSON.
  const nlohmann::json every = read_json(json);  // kept: a loop over a temporary's member would outlive it
  for (const nlohmann::json& l : every["located"]) {
    const std::string why = l["not_confident_because"].get<std::string>();
    EXPECT_EQ(l["confident"].get<bool>(), why.empty()) << why;
    if (!why.empty()) {
      EXPECT_THAT(run.output, HasSubstr("(low: " + why + ")"));
    }
  }
  EXPECT_THAT(run.output, HasSubstr("0.0 .. 2.0 m of travel, log time "));  // both clocks, as match's label
  ASSERT_EQ(run_partslam("export-map sim:1 --until 10 --out " + quoted(dir_ / "first.yaml")).exit_code, 0);
  EXPECT_LT(fs::file_size(dir_ / "first.pgm"), fs::file_size(dir_ / "building.pgm"));
}

// --track follows the log through the map exported from it: localised within a few steps, every localised
// robot pose where the log says the robot was, the hypotheses in the JSON, the picture written; and it goes
// with --query-log alone.
TEST_F(CliLocateTest, TrackFollowsTheLogThroughItsMap) {
  const fs::path yaml = dir_ / "building.yaml", json = dir_ / "tracked.json", png = dir_ / "tracked.png";
  ASSERT_EQ(run_partslam("export-map sim:1 --out " + quoted(yaml)).exit_code, 0);
  CliRun run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --track --every 4 --quiet --json " +
                            quoted(json) + " --plot " + quoted(png));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("localised; "));
  EXPECT_TRUE(fs::exists(png));
  const Scans scans = io::load_scan_source("sim:1").scans;
  const std::vector<double> s = travel_distances(scans);
  const nlohmann::json j = read_json(json);  // kept: loops read its members
  ASSERT_GT(j["tracked"].size(), 10u);
  std::size_t localised = 0, first = 0, k = 0;
  for (const nlohmann::json& t : j["tracked"]) {
    ++k;
    ASSERT_TRUE(t.contains("status") && t.contains("hypotheses") && t.contains("log_time")) << t.dump();
    if (t["status"] != "localised") continue;
    if (localised++ == 0) first = k;
    // The robot pose at the local map's first scan (its log time), from the log's own poses.
    const double from = t["log_time"]["from"].get<double>();
    std::size_t i = 0;
    while (i + 1 < scans.size() && scans[i].timestamp < from - 1e-6) ++i;
    const Pose2& truth = scans[i].T_world_laser;
    EXPECT_NEAR(t["robot_pose"]["x"].get<double>(), truth.x, 0.3) << t["query"];
    EXPECT_NEAR(t["robot_pose"]["y"].get<double>(), truth.y, 0.3) << t["query"];
    EXPECT_NEAR(wrap_angle(t["robot_pose"]["theta"].get<double>() - truth.theta), 0.0, 3 * kDegree) << t["query"];
    EXPECT_NEAR(t["robot_pose_time"].get<double>(), scans[i].timestamp, 1e-6);
    // Where it is at the end of the step: the local map's last scan.
    const double to = t["log_time"]["to"].get<double>();
    std::size_t k = i;
    while (k + 1 < scans.size() && scans[k].timestamp < to - 1e-6) ++k;
    EXPECT_NEAR(t["robot_pose_now_time"].get<double>(), to, 1e-6);
    EXPECT_NEAR(t["robot_pose_now"]["x"].get<double>(), scans[k].T_world_laser.x, 0.3) << t["query"];
    EXPECT_NEAR(t["robot_pose_now"]["y"].get<double>(), scans[k].T_world_laser.y, 0.3) << t["query"];
    EXPECT_GE(t["probability"].get<double>(), 0.5);
    EXPECT_GE(t["hypotheses"].size(), 1u);
  }
  EXPECT_GE(localised, j["tracked"].size() * 3 / 4);
  EXPECT_LE(first, 5u);
  EXPECT_THAT(run.output, Not(HasSubstr("hint:")));
  // A map of the log's first 10 m: most steps lie outside it, and the run says what else could be wrong.
  ASSERT_EQ(run_partslam("export-map sim:1 --until 10 --out " + quoted(dir_ / "first.yaml")).exit_code, 0);
  run = run_partslam("locate --map " + quoted(dir_ / "first.yaml") + " --query-log sim:1 --track --every 4 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("hint: fewer than half the steps were localised"));
  run = run_partslam("locate --map " + quoted(yaml) + " --query-log sim:1 --track --from 1 --to 3");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.output, HasSubstr("--track goes with --query-log alone"));
}

// A stored map exported as a point file (world frame) and queried with --query-points: match ranks that map
// first, locate puts the file's frame on the map frame and, the file carrying the map's laser origins,
// verifies its free space too (a calibrated probability).
TEST_F(CliLocateTest, QueryPointsFromAFile) {
  const fs::path db = dir_ / "m.db", points = dir_ / "map20.csv", yaml = dir_ / "b.yaml", json = dir_ / "r.json";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  ASSERT_EQ(run_partslam("export " + quoted(db) + " --map 20 --frame world --out " + quoted(points)).exit_code, 0);
  CliRun run = run_partslam("match " + quoted(db) + " --query-points " + quoted(points) + " --method dmm --top 1 --json " +
                            quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  nlohmann::json j = read_json(json);
  EXPECT_EQ(j["ranking"][0]["map"].get<int>(), 20);
  EXPECT_GT(j["ranking"][0]["inlier_fraction"].get<double>(), 0.95);
  ASSERT_EQ(run_partslam("export-map sim:1 --out " + quoted(yaml)).exit_code, 0);
  run = run_partslam("locate --map " + quoted(yaml) + " --query-points " + quoted(points) + " --json " + quoted(json));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  j = read_json(json);
  const nlohmann::json& frame = j["located"][0]["T_map_source"];
  EXPECT_NEAR(frame["theta"].get<double>(), 0.0, 0.05);
  EXPECT_TRUE(j["located"][0]["calibrated"].get<bool>());
  EXPECT_THAT(j["located"][0]["query"].get<std::string>(), HasSubstr("with its laser origins"));
  // The file's points land on themselves, checked where they are: they lie ~20 m from the world origin, so the
  // 0.8 degrees a local map of 0.1 m cells leaves open moves the origin by 0.27 m and the points by 1 cm.
  const Pose2 T_map_source{frame["x"].get<double>(), frame["y"].get<double>(), frame["theta"].get<double>()};
  const Points2 file_points = io::read_points(points);
  ASSERT_FALSE(file_points.empty());
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : file_points) centre += p / static_cast<double>(file_points.size());
  EXPECT_LT((T_map_source * centre - centre).norm(), 0.1);
}

// A query whose own Manhattan frame is half a quarter turn from the stored map's (three long diagonal walls
// added to stored map 20 outweigh its axis walls): match searches the ranking's eight rotation families by
// default, as eval and the Python Ranker do, and finds the place at 45 degrees; four families (the multiples
// of 90 degrees only) cannot.
TEST_F(CliLocateTest, MatchSearchesEightRotationFamiliesByDefault) {
  const fs::path db = dir_ / "t.db", exported = dir_ / "map20.csv", points = dir_ / "diagonal.csv";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  ASSERT_EQ(
      run_partslam("export " + quoted(db) + " --map 20 --frame world --out " + quoted(exported)).exit_code,
      0);
  Points2 query = io::read_points(exported);
  ASSERT_FALSE(query.empty());
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : query) centre += p / static_cast<double>(query.size());
  const Vec2 along = Vec2(1.0, 1.0).normalized(), across(-along.y(), along.x());
  for (const double offset : {-1.5, 0.0, 1.5})
    for (int i = -80; i <= 80; ++i) query.push_back(centre + 0.05 * i * along + offset * across);
  std::string csv = "x,y\n";
  for (const Vec2& p : query) csv += std::to_string(p.x()) + "," + std::to_string(p.y()) + "\n";
  write(points, csv);
  std::map<std::string, nlohmann::json> best;
  for (const std::string turns : {"", " --dmm-turns 8", " --dmm-turns 4"}) {
    const fs::path json = dir_ / "turns.json";
    const CliRun run = run_partslam("match " + quoted(db) + " --query-points " + quoted(points) +
                                    " --method dmm:eq1 --top 1 --json " + quoted(json) + turns);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    best[turns] = read_json(json)["ranking"][0];
  }
  EXPECT_EQ(best[""], best[" --dmm-turns 8"]);
  const double theta = best[""]["T_map_query"]["theta"].get<double>();
  EXPECT_NEAR(std::remainder(theta - std::numbers::pi / 4, std::numbers::pi / 2), 0.0, 0.05) << theta;
  EXPECT_NEAR(best[""]["map"].get<int>(), 20, 2);  // the place: map 20 or a neighbour along the path
  EXPECT_GT(best[""]["inlier_fraction"].get<double>(), 0.5);
  EXPECT_LT(best[" --dmm-turns 4"]["inlier_fraction"].get<double>(),
            best[""]["inlier_fraction"].get<double>() - 0.2);
  EXPECT_THAT(run_partslam("match " + quoted(db) + " --query 20 --dmm-turns 5").output,
              HasSubstr("canonical_turns must be 4 or 8"));
}

// A stored map exported in either frame and either format gives the same local map (same points, same pose): the
// map-frame file names its frame's pose, and the query takes the points back into that world frame before building the local map.
TEST_F(CliLocateTest, APointFileRoundTripsInEitherFrame) {
  const fs::path db = dir_ / "f.db";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db)).exit_code, 0);
  std::vector<nlohmann::json> rankings;
  std::vector<std::string> labels;
  for (const std::string frame : {"world", "map"}) {
    for (const std::string format : {"csv", "ply"}) {
      const fs::path points = dir_ / ("map20_" + frame + "." + format), json = dir_ / ("r_" + frame + format + ".json");
      CliRun run = run_partslam("export " + quoted(db) + " --map 20 --frame " + frame + " --out " + quoted(points));
      ASSERT_EQ(run.exit_code, 0) << run.output;
      run = run_partslam("match " + quoted(db) + " --query-points " + quoted(points) +
                         " --method dmm --top 2 --json " + quoted(json) + kNarrowDmm);
      ASSERT_EQ(run.exit_code, 0) << run.output;
      const nlohmann::json j = read_json(json);
      EXPECT_EQ(j["ranking"][0]["map"].get<int>(), 20) << frame << " " << format;
      EXPECT_GT(j["ranking"][0]["inlier_fraction"].get<double>(), 0.95) << frame << " " << format;
      EXPECT_NEAR(j["ranking"][0]["T_map_query"]["theta"].get<double>(), 0.0, 0.01) << frame << " " << format;
      rankings.push_back(j["ranking"]);
      const std::string label = j["query"].get<std::string>();
      labels.push_back(label.substr(label.find(" points") - 4, 4));  // the point count
    }
  }
  // The same answer from every file (PLY stores single floats: the refined poses agree to 1e-4).
  for (std::size_t i = 1; i < rankings.size(); ++i) {
    ASSERT_EQ(rankings[i].size(), rankings[0].size()) << i;
    for (std::size_t k = 0; k < rankings[0].size(); ++k) {
      EXPECT_EQ(rankings[i][k]["map"], rankings[0][k]["map"]) << i;
      EXPECT_EQ(rankings[i][k]["inliers"], rankings[0][k]["inliers"]) << i;
      for (const char* field : {"x", "y", "theta"})
        EXPECT_NEAR(rankings[i][k]["T_map_query"][field].get<double>(),
                    rankings[0][k]["T_map_query"][field].get<double>(), 1e-4) << i;
    }
    EXPECT_EQ(labels[i], labels[0]) << i;
  }
}

// --json on the commands that build and store: what they printed, machine-readable; a map_server map as a
// dictionary source.
TEST_F(CliLocateTest, JsonOfSubmapsDictionaryAndDescribe) {
  const fs::path db = dir_ / "j.db", yaml = dir_ / "d.yaml";
  ASSERT_EQ(run_partslam("submaps sim:1 --db " + quoted(db) + " --json " + quoted(dir_ / "s.json")).exit_code, 0);
  const nlohmann::json s = read_json(dir_ / "s.json");
  EXPECT_EQ(s["dataset"], "sim-1");
  EXPECT_GT(s["submaps"].get<int>(), 100);
  ASSERT_EQ(run_partslam("export-map sim:2 --out " + quoted(yaml)).exit_code, 0);
  CliRun run = run_partslam("dictionary " + quoted(yaml) + " --db " + quoted(db) + " --json " + quoted(dir_ / "d.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json d = read_json(dir_ / "d.json");
  EXPECT_EQ(d["dictionary"], "d");
  EXPECT_GT(d["points"].get<int>(), 500);
  run = run_partslam("describe " + quoted(db) + " --dict d --k 3 --parts 20 --quiet --json " + quoted(dir_ / "c.json"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json c = read_json(dir_ / "c.json");
  EXPECT_EQ(c["maps"], s["submaps"]);
  ASSERT_EQ(c["sets"].size(), 2u);  // K = 3 and the query list P = 20
  EXPECT_EQ(c["sets"][0]["k"], 3);
}

// Bad input: a clear message naming the file or field, exit 1, nothing written.
TEST_F(CliLocateTest, BadInputIsRefusedWithTheFileNamed) {
  const fs::path yaml = dir_ / "b.yaml", json = dir_ / "out.json";
  ASSERT_EQ(run_partslam("export-map sim:1 --out " + quoted(yaml)).exit_code, 0);
  write(dir_ / "noimage.yaml", "image: gone.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  write(dir_ / "short.pgm", "P5\n100 100\n255\n" + std::string(10, '\xfe'));
  write(dir_ / "short.yaml", "image: short.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  write(dir_ / "empty.csv", "x,y\n");
  write(dir_ / "nan.csv", "1,2\nnan,3\n");
  const std::string log = " --query-log sim:1 --from 10 --to 12 --json " + quoted(json);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"locate --map " + quoted(dir_ / "noimage.yaml") + log, "noimage.yaml: field 'image'"},
      {"locate --map " + quoted(dir_ / "short.yaml") + log, "short.pgm: truncated PGM"},
      {"locate --map " + quoted(dir_ / "none.yaml") + log, "none.yaml: cannot open"},
      {"locate --map " + quoted(yaml) + " --query-points " + quoted(dir_ / "empty.csv"), "empty.csv: no points"},
      {"locate --map " + quoted(yaml) + " --query-points " + quoted(dir_ / "nan.csv"), "nan.csv:2: x: not finite"},
      {"locate --map " + quoted(yaml), "give --query-log LOG or --query-points FILE"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --every 5 --from 1 --to 3", "--every goes with"},
      // --every 0 is a bad --every, not a missing stretch; no stretch at all names --every among them.
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --every 0", "--every must be a positive number of metres, got 0"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --every -2", "--every must be a positive number"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1", "or --every M"},
      {"locate --map " + quoted(yaml) + " --query-log sim:1 --from 1 --to 3 --query-points " + quoted(dir_ / "nan.csv"),
       "not both"},
      {"export-map sim:1 --out " + quoted(dir_ / "map.png"), "--out must name the map's YAML"},
      {"export-map sim:1 --out " + quoted(dir_ / "nowhere" / "m.yaml"), "does not exist"},
  };
  for (const auto& [args, message] : cases) {
    const CliRun r = run_partslam(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr(message)) << args;
  }
  EXPECT_FALSE(fs::exists(json));
}

}  // namespace
}  // namespace partslam
