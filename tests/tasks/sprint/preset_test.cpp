// The sprint's presets as data (tasks/sprint/data/presets.json) and their errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "podium/base/error.h"
#include "sprint_preset.h"

namespace podium::tasks::sprint {
namespace {

TEST(SprintPreset, ShippedPresetsSetTheTrackLengthAndNNorm) {
  EXPECT_EQ(load_sprint_preset("smoke").track.length_m, 10.0);
  EXPECT_EQ(load_sprint_preset("quick").track.length_m, 30.0);
  const SprintPreset paper = load_sprint_preset("paper");
  EXPECT_EQ(paper.track.length_m, 100.0);
  EXPECT_EQ(paper.track.lane_width_m, 1.22);
  EXPECT_GT(paper.steps.n_norm, load_sprint_preset("quick").steps.n_norm);
  EXPECT_EQ(paper.drag.cda_m2, 0.25);
  EXPECT_EQ(paper.drag.air_density, 1.2);
  EXPECT_EQ(paper.wind_mps.hi, 2.0);
  EXPECT_EQ(paper.friction.lo, 0.8);
  // The race report's DR episodes: a few for CI, the issue's 20 and 100.
  EXPECT_EQ(load_sprint_preset("smoke").race.episodes, 2);
  EXPECT_EQ(load_sprint_preset("quick").race.episodes, 20);
  EXPECT_EQ(paper.race.episodes, 100);
}

TEST(SprintPreset, EpisodeDrawsStayInTheRangesAndRepeatPerSeed) {
  const SprintPreset quick = load_sprint_preset("quick");
  base::Rng a(3), b(3);
  double wind_lo = 1e9, wind_hi = -1e9;
  for (int k = 0; k < 2000; ++k) {
    const EpisodeDraw d = draw_episode(quick, a);
    EXPECT_EQ(d.to_json(), draw_episode(quick, b).to_json());
    EXPECT_GE(d.wind_mps, -2.0);
    EXPECT_LE(d.wind_mps, 2.0);
    EXPECT_GE(d.friction, 0.8);
    EXPECT_LE(d.friction, 1.2);
    wind_lo = std::min(wind_lo, d.wind_mps);
    wind_hi = std::max(wind_hi, d.wind_mps);
  }
  EXPECT_LT(wind_lo, -1.9);  // the whole range is drawn
  EXPECT_GT(wind_hi, 1.9);
}

TEST(SprintPreset, TheStartPhasesImitationSettingsAreData) {
  for (const char* name : {"smoke", "quick", "paper"}) {
    const StartPreset start = load_sprint_preset(name).start;
    EXPECT_EQ(start.imitation_weight, 10.0) << name;            // λ_i: r_I ≤ 1 against r_base's 3-4 per step
    EXPECT_EQ(start.weights.pose, 0.65) << name;                // DeepMimic's r_I
    EXPECT_EQ(start.weights.end_effector_scale, 10.0) << name;  // DeepMimic's code: end effectors from the root
    EXPECT_EQ(start.max_com_deviation_m, 0.5) << name;
    EXPECT_EQ(start.landing_x_m, 0.5) << name;
  }
}

TEST(SprintPreset, BadValuesAreOneLineNamingTheirPath) {
  auto error = [](const base::Json& preset) {
    try {
      base::ConfigReader::parse(preset, "presets.json", read_sprint_preset);
    } catch (const base::UserError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string length = error(base::Json::parse(R"({"track": {"length_m": -5}})"));
  EXPECT_NE(length.find("presets.json: track.length_m: -5"), std::string::npos) << length;
  const std::string range = error(base::Json::parse(R"({"randomise": {"wind_mps": [2, -2]}})"));
  EXPECT_NE(range.find("randomise.wind_mps"), std::string::npos) << range;
  const std::string unknown = error(base::Json::parse(R"({"steps": {"n_nrom": 5}})"));
  EXPECT_NE(unknown.find("n_nrom"), std::string::npos) << unknown;
  EXPECT_EQ(unknown.find('\n'), std::string::npos);
  const std::string race = error(base::Json::parse(R"({"race": {"episodes": 0}})"));
  EXPECT_NE(race.find("race.episodes: 0"), std::string::npos) << race;
  // w_primitive is the accelerate stage's (primitive_weight, with its clips), not the track's.
  for (const char* name : {"smoke", "quick", "paper"}) EXPECT_EQ(load_sprint_preset(name).rewards.primitive, 0.0) << name;
  const std::string primitive = error(base::Json::parse(R"({"rewards": {"primitive": 0.5}})"));
  EXPECT_NE(primitive.find("rewards.primitive"), std::string::npos) << primitive;
  const std::string lambda = error(base::Json::parse(R"({"start": {"imitation_weight": -1}})"));
  EXPECT_NE(lambda.find("presets.json: start.imitation_weight: -1"), std::string::npos) << lambda;
  // The dip's fall penalty is data, and above the time limit so that every finisher beats a fall.
  for (const char* name : {"smoke", "quick", "paper"}) {
    const SprintPreset p = load_sprint_preset(name);
    EXPECT_GT(p.dip.fall_penalty_s, p.time_limit_s) << name;
  }
  const std::string penalty = error(base::Json::parse(R"({"episode": {"time_limit_s": 20}, "dip": {"fall_penalty_s": 15}})"));
  EXPECT_NE(penalty.find("presets.json: dip"), std::string::npos) << penalty;
  EXPECT_NE(penalty.find("must exceed episode.time_limit_s 20"), std::string::npos) << penalty;
  try {
    load_sprint_preset("marathon");
    FAIL() << "no error";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("no preset \"marathon\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("presets.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace podium::tasks::sprint
