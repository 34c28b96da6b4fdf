// Test-only task plugin "web_replay_fixture": writes a trajectory artifact (sim/'s trajectory
// file, JSON lines, sim/README.md) for the browser tests, until a physics task records real ones. The
// motion is analytic on purpose: a chain of three capsules and a ball swinging under a bar
// (a box prop) beside an inclined block, over a patch of rough tiles (heights of either sign);
// parameters set the amplitude and the rate. Not physics; nothing else uses it.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "podium/plugins/export.h"

namespace podium::tests::web_dashboard {

using base::Json;

class ReplayFixtureTask final : public plugins::Task {
 public:
  Json describe(const Json&) const override {
    return {{"params", {{{"name", "amplitude"}, {"low", 0.2}, {"high", 1.2}}, {{"name", "rate"}, {"low", 1.0}, {"high", 4.0}}}},
            {"features",
             {{{"name", "tip_height"}, {"low", 0.0}, {"high", 2.0}, {"metric", "euclidean"}},
              {{"name", "final_angle"}, {"low", -2.0}, {"high", 2.0}, {"metric", "euclidean"}}}},
            {"metrics", {{{"name", "return"}}, {{"name", "curriculum/level"}}}},
            {"objectives", {"tip_height"}},
            {"presets", {{"smoke", Json::object()}, {"quick", Json::object()}, {"paper", Json::object()}}},
            {"config_defaults", Json::object()}};
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const double amplitude = request.params.at("amplitude").get<double>(), rate = request.params.at("rate").get<double>();
    constexpr int kLinks = 3, kFrames = 90;
    constexpr double kLength = 0.4, kDt = 1.0 / 30.0, kPi = 3.14159265358979323846;
    const double bar_z = 2.0;
    // Header line: links with their shapes (capsules along local z), a ball, and the bar as a prop.
    Json links = Json::array(), names = Json::array();
    for (int i = 0; i <= kLinks; ++i) {
      const bool ball = i == kLinks;
      const std::string name = ball ? "ball" : "link" + std::to_string(i);
      const Json shape = ball ? Json{{"type", "sphere"}, {"body", name}, {"radius", 0.09}}
                              : Json{{"type", "capsule"}, {"body", name}, {"radius", 0.05}, {"half_length", 0.15}};
      links.push_back({{"name", name}, {"parent", i == 0 ? Json(nullptr) : Json(i - 1)}, {"shapes", {shape}}});
      names.push_back(name);
    }
    // Terrain as sim::write_trajectory writes it: a 4 × 4 m region of 0.5 m tiles, each a box
    // from half a metre below its top (or below 0) up to a top within ±8 cm.
    constexpr double kTile = 0.5, kDepth = 0.5;
    Json pieces = Json::array();
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 8; ++j) {
        const double top = 0.08 * std::sin(1.7 * i + 2.3 * j), bottom = std::min(top, 0.0) - kDepth;
        pieces.push_back({{"region", 0},
                          {"type", "box"},
                          {"pos", {-2 + kTile * (i + 0.5), -2 + kTile * (j + 0.5), (top + bottom) / 2}},
                          {"quat", {1, 0, 0, 0}},
                          {"half_extents", {kTile / 2, kTile / 2, (top - bottom) / 2}}});
      }
    }
    const Json terrain = {{"regions", {{{"kind", "rough"}, {"min", {-2, -2}}, {"max", {2, 2}}}}}, {"pieces", pieces}};
    const double tilt = 0.35;  // an inclined starting block, turned about y
    const Json props = {{{"name", "bar"},
                         {"type", "box"},
                         {"half_extents", {0.05, 0.6, 0.05}},
                         {"pos", {0.0, 0.0, bar_z}},
                         {"quat", {1, 0, 0, 0}}},
                        {{"name", "block"},
                         {"type", "box"},
                         {"half_extents", {0.3, 0.25, 0.1}},
                         {"pos", {0.9, 0.0, 0.2}},
                         {"quat", {std::cos(tilt / 2), 0.0, std::sin(tilt / 2), 0.0}}}};
    const Json header = {
        {"format", "podium-trajectory"}, {"version", 2},   {"model", "fixture-chain"}, {"links", links},    {"bodies", names},
        {"joints", Json::array()},       {"ground", true}, {"props", props},           {"terrain", terrain}};
    const auto path = request.work_dir / "trajectory.jsonl";
    std::ofstream out(path);
    out << header.dump() << '\n';
    double tip_z = 0, max_tip_z = -1e9, angle = 0;
    for (int f = 0; f < kFrames; ++f) {
      const double t = f * kDt;
      double px = 0, pz = bar_z;
      Json poses = Json::array();
      for (int i = 0; i < kLinks; ++i) {
        angle = amplitude * (1.0 + 0.3 * i) * std::sin(rate * t + 0.5 * i);
        const double dx = std::sin(angle), dz = -std::cos(angle), phi = kPi - angle;  // local z onto (dx, 0, dz)
        poses.push_back({px + dx * kLength / 2, 0.0, pz + dz * kLength / 2, std::cos(phi / 2), 0.0, std::sin(phi / 2), 0.0});
        px += dx * kLength;
        pz += dz * kLength;
      }
      poses.push_back({px, 0.0, pz, 1.0, 0.0, 0.0, 0.0});
      tip_z = pz;
      max_tip_z = std::max(max_tip_z, tip_z);
      out << Json{{"t", t},         {"root", poses[0]},         {"q", Json::array()},       {"qd", Json::array()},
                  {"links", poses}, {"com", {px / 2, 0.0, pz}}, {"contacts", Json::array()}}
                 .dump()
          << '\n';
    }
    out.close();
    for (int k = 0; k < 20; ++k) {
      sink.metric("return", k, max_tip_z * (1.0 - std::exp(-0.2 * k)));
      sink.metric("curriculum/level", k, std::floor(k / 5.0));
    }
    plugins::RunResult result;
    result.objectives = {max_tip_z};
    result.features = {max_tip_z, angle};
    result.info["summary"] = {{"tip peak m", max_tip_z}};  // the strategy gallery shows it
    result.artifacts.push_back({"trajectory", path});
    // A second motion: the same frames from t = 2 s, as a get-up's fast run begins after its 2 s
    // fall while its slowed runs begin at 0 (the replay plays both from their first frames).
    std::ifstream in(path);
    std::ofstream fast(request.work_dir / "trajectory_fast.jsonl");
    for (std::string line; std::getline(in, line);) {
      Json row = Json::parse(line);
      if (row.contains("t")) row["t"] = row["t"].get<double>() + 2.0;
      fast << row.dump() << '\n';
    }
    result.artifacts.push_back({"trajectory_fast", request.work_dir / "trajectory_fast.jsonl"});
    return result;
  }
};

}  // namespace podium::tests::web_dashboard

PODIUM_EXPORT_TASK(podium::tests::web_dashboard::ReplayFixtureTask, "web_replay_fixture")
