#include "io/formats/config_file.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

// The error read_config_file gives for a file holding `text`, or "" when it reads it.
template <class Config>
std::string refusal(const testing::TempDir& dir, const std::string& text) {
  testing::write_text(dir / "settings.yaml", text, false);
  Config config;
  try {
    read_config_file(dir / "settings.yaml", config);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigFile, TheWrittenDefaultsReadBackUnchanged) {
  testing::TempDir dir;
  SlamConfig slam;
  slam.back_end.weights.loop_rotation = 123.25;
  slam.front_end.matcher.sigma = 0.1 / 3;
  slam.loops.method = "rerank:5";
  slam.loops.graph_check = false;
  slam.submaps.min_points = 7;
  slam.min_confidence = -0.5;
  const std::string text = config_yaml(slam);
  EXPECT_THAT(text, HasSubstr("\nback_end:\n  weights:\n    chain_translation: 400.0\n"));
  EXPECT_THAT(text, HasSubstr("  method: \"rerank:5\"\n"));
  testing::write_text(dir / "slam.yaml", text, false);
  SlamConfig read;
  read_config_file(dir / "slam.yaml", read);
  EXPECT_EQ(config_yaml(read), text);
  EXPECT_EQ(read.front_end.matcher.sigma, 0.1 / 3);
  EXPECT_FALSE(read.loops.graph_check);

  LoopsConfig loops;
  loops.truth.radius = 3.5;
  testing::write_text(dir / "loops.yaml", config_yaml(loops), false);
  LoopsConfig loops_read;
  read_config_file(dir / "loops.yaml", loops_read);
  EXPECT_EQ(config_yaml(loops_read), config_yaml(loops));
  EXPECT_EQ(loops_read.truth.radius, 3.5);

  LocateConfig locate;
  locate.localizer.candidates = 9;
  locate.localizer.dmm.canonical_turns = 8;
  testing::write_text(dir / "locate.yaml", config_yaml(locate), false);
  LocateConfig locate_read;
  read_config_file(dir / "locate.yaml", locate_read);
  EXPECT_EQ(config_yaml(locate_read), config_yaml(locate));
  EXPECT_EQ(locate_read.localizer.dmm.canonical_turns, 8);
}

TEST(ConfigFile, KeysLeftOutKeepTheirValues) {
  testing::TempDir dir;
  testing::write_text(dir / "some.yaml", "back_end:\n  max_rounds: 5\nmin_confidence: 0.5\n", false);
  SlamConfig c;
  c.submaps.spacing = 0.75;  // not in the file: stays
  read_config_file(dir / "some.yaml", c);
  EXPECT_EQ(c.back_end.max_rounds, 5);
  EXPECT_EQ(c.min_confidence, 0.5);
  EXPECT_EQ(c.submaps.spacing, 0.75);
  EXPECT_EQ(c.back_end.max_rejected_share, BackEndConfig{}.max_rejected_share);
  testing::write_text(dir / "empty.yaml", "", false);
  EXPECT_NO_THROW(read_config_file(dir / "empty.yaml", c));
}

TEST(ConfigFile, UnknownKeysAreRefusedNamingKeyAndFile) {
  testing::TempDir dir;
  const std::string e = refusal<SlamConfig>(dir, "front_end:\n  fine_sigma: 0.05\n  matchr:\n    sigma: 1\n");
  EXPECT_THAT(e, HasSubstr("settings.yaml: line 3: unknown key 'front_end.matchr'"));
  EXPECT_THAT(e, HasSubstr("matcher"));  // the keys it could be
  EXPECT_THAT(refusal<SlamConfig>(dir, "huber: 1\n"), HasSubstr("settings.yaml: line 1: unknown key 'huber'"));
  // The truth's travel gap is the loops' and has no key of its own.
  EXPECT_THAT(refusal<LoopsConfig>(dir, "truth:\n  min_travel_gap: 3\n"),
              HasSubstr("unknown key 'truth.min_travel_gap'"));
  EXPECT_THAT(refusal<LocateConfig>(dir, "localizer:\n  dmm:\n    resolutoin: 0.1\n"),
              HasSubstr("line 3: unknown key 'localizer.dmm.resolutoin'"));
}

TEST(ConfigFile, WrongTypesAreRefusedNamingFieldAndFile) {
  testing::TempDir dir;
  EXPECT_THAT(refusal<SlamConfig>(dir, "back_end:\n  max_rounds: many\n"),
              HasSubstr("settings.yaml: line 2: back_end.max_rounds: expected an integer, got 'many'"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "back_end:\n  max_rounds: 2.5\n"),
              HasSubstr("back_end.max_rounds: expected an integer, got '2.5'"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "min_confidence: [1, 2]\n"),
              HasSubstr("min_confidence: expected a number, got a list"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "loops:\n  graph_check: maybe\n"),
              HasSubstr("loops.graph_check: expected true or false, got 'maybe'"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "back_end: 3\n"), HasSubstr("back_end: expected a map of settings"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "- a\n- b\n"), HasSubstr("settings.yaml: expected a map of settings"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "a: [\n"), HasSubstr("settings.yaml: line 2: not valid YAML"));
  EXPECT_THAT(refusal<SlamConfig>(dir, std::string("\x89PNG\r\n\x1a\n\0\0", 10)),
              HasSubstr("settings.yaml: binary data, not a YAML settings file"));
  SlamConfig c;
  EXPECT_THAT([&] { read_config_file(dir / "missing.yaml", c); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("missing.yaml: cannot open")));
}

TEST(ConfigFile, ValuesOutOfRangeAreRefusedNamingFieldAndFile) {
  testing::TempDir dir;
  EXPECT_THAT(refusal<SlamConfig>(dir, "back_end:\n  weights:\n    loop_rotation: -1\n"),
              HasSubstr("settings.yaml: slam config: back_end.weights.loop_rotation must be finite and > 0, got -1"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "front_end:\n  matcher:\n    sigma: .nan\n"),
              HasSubstr("settings.yaml: slam config: front_end.matcher.sigma must be"));
  EXPECT_THAT(refusal<LoopsConfig>(dir, "loops:\n  other_place: 0\n"),
              HasSubstr("settings.yaml: loops config: loops.other_place must be"));
  EXPECT_THAT(refusal<LoopsConfig>(dir, "truth:\n  radius: -2\n"),
              HasSubstr("settings.yaml: loops config: truth.radius must be"));
  EXPECT_THAT(refusal<LocateConfig>(dir, "localizer:\n  candidates: 1\n"),
              HasSubstr("settings.yaml: locate config: localizer.candidates must be in [2, 100]"));
  EXPECT_THAT(
      refusal<LocateConfig>(dir, "localizer:\n  candidate_distance: 3\n"),
      HasSubstr(
          "settings.yaml: locate config: localizer.candidate_distance must be in (0, elsewhere_distance]"));
  EXPECT_THAT(refusal<LocateConfig>(dir, "localizer:\n  dmm:\n    resolution: -1\n"),
              HasSubstr("settings.yaml: locate config: localizer.dmm.resolution must be"));
  EXPECT_THAT(refusal<LocateConfig>(dir, "submaps:\n  window_length: 0\n"),
              HasSubstr("settings.yaml: locate config: submaps.window_length must be"));
  // The loops' method is checked as the file is read, not after `slam`'s front end has run.
  EXPECT_THAT(refusal<SlamConfig>(dir, "loops:\n  method: bogus\n"),
              HasSubstr("settings.yaml: slam config: loops.method 'bogus': unknown scheme"));
  EXPECT_THAT(refusal<LoopsConfig>(dir, "loops:\n  method: succinct\n"),
              HasSubstr("settings.yaml: loops config: loops.method 'succinct' gives no dMM pose"));
  EXPECT_THAT(refusal<SlamConfig>(dir, "loops:\n  method: rerank:5:3\n"),
              HasSubstr("loops.method 'rerank:5:3' needs CPD parts"));
}

TEST(ConfigFile, StringsAreWrittenWithTheirControlCharactersEscaped) {
  // A raw line break inside a double-quoted YAML scalar reads back as a space (found by fuzz_config).
  LoopsConfig c;
  c.loops.method = "a\nb\t\"c\\\x7f";
  EXPECT_THAT(config_yaml(c), HasSubstr("\n  method: \"a\\x0ab\\x09\\\"c\\\\\\x7f\"\n"));
}

}  // namespace
}  // namespace partslam::io
