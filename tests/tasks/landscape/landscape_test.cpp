// The task conformance suite (task_conformance.h) applied to the landscape task, with noise so
// that its smoke trials check the seeded noise is deterministic; plus its config errors and families.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "landscape_model.h"
#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/plugins/loader.h"
#include "process.h"
#include "task_conformance.h"

namespace podium::tasks::landscape {
namespace {

using base::Json;

struct NullSink : plugins::Sink {
  int metrics = 0;
  void progress(double) override {}
  void metric(const std::string&, double, double) override { ++metrics; }
};

plugins::RunRequest request_for(const Json& config, std::uint64_t seed) {
  plugins::RunRequest r;
  r.config = config;
  r.params = {{"x0", 0.2}, {"x1", 0.7}, {"x2", 0.4}};
  r.seed = seed;
  return r;
}

PODIUM_TASK_CONFORMANCE(Landscape, {.task = "landscape",
                                    .smoke_config = {{"artifact", true}, {"noise", 0.05}},
                                    .long_config = {{"sleep_s", 60.0}},
                                    .resume_config = {{"sleep_s", 1.5}},
                                    .artifacts = {"result"}});

// The suite runs one seed twice; the noise must also change with the seed.
TEST(LandscapeTask, NoiseDependsOnTheSeed) {
  auto task = plugins::load_task("landscape");
  const Json config = {{"noise", 0.05}};
  NullSink sink;
  const auto a = task->run(request_for(config, 11), sink);
  const auto b = task->run(request_for(config, 12), sink);
  EXPECT_NE(a.features, b.features);
  EXPECT_EQ(sink.metrics, 2 * 5);
}

TEST(LandscapeTask, ConfigErrorsNameTheKeyInsideTheConfig) {
  auto task = plugins::load_task("landscape");
  for (const auto& [config, path] :
       std::vector<std::pair<Json, std::string>>{{{{"dimm", 3}}, "dimm"},
                                                 {{{"family", "plateus"}}, "family"},
                                                 {{{"failures", {{{"mode", "nap"}}}}}, "failures[0].mode"}}) {
    try {
      task->describe(config);
      ADD_FAILURE() << config << " was accepted";
    } catch (const base::ConfigError& e) {
      EXPECT_EQ(e.path(), path) << e.what();
    }
    plugins::RunRequest r = request_for(config, 1);
    NullSink sink;
    EXPECT_THROW(task->run(r, sink), base::ConfigError) << config;  // run() checks as describe() does
  }
}

// Each family has a few large flat regions: sampling finds several distinct features, and the
// most common one covers a sizeable share of the box.
TEST(LandscapeModel, EveryFamilyHasSeveralFlatRegions) {
  for (const auto& family : LandscapeModel::families()) {
    const LandscapeModel model({family, 3, 5, 6});
    base::Rng rng(3);
    std::map<std::vector<double>, int> counts;
    for (int i = 0; i < 4000; ++i) counts[model.feature({rng.uniform(), rng.uniform(), rng.uniform()})]++;
    int largest = 0;
    for (const auto& [f, n] : counts) largest = std::max(largest, n);
    EXPECT_GE(counts.size(), 2u) << family;
    EXPECT_GE(largest, 400) << family;
  }
}

// "plateaus" is "plateaus_rough" with frequencies scaled by 1/1.5 (same random draws otherwise):
// its trend changes less over a short step, which is what makes it learnable from few samples.
TEST(LandscapeModel, PlateausTrendIsSmootherThanTheRoughOne) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const LandscapeModel smooth({"plateaus", 3, seed, 6}), rough({"plateaus_rough", 3, seed, 6});
    base::Rng rng(seed);
    double smooth_change = 0.0, rough_change = 0.0;
    for (int i = 0; i < 500; ++i) {
      const std::vector<double> a = {rng.uniform(0.0, 0.95), rng.uniform(0.0, 0.95), rng.uniform(0.0, 0.95)};
      const std::vector<double> b = {a[0] + 0.05, a[1], a[2]};
      smooth_change += std::abs(smooth.trend(a)[0] - smooth.trend(b)[0]);
      rough_change += std::abs(rough.trend(a)[0] - rough.trend(b)[0]);
    }
    EXPECT_LT(smooth_change, rough_change) << seed;
  }
}

TEST(LandscapeModel, TrendNeedsAPlateauFamily) {
  const LandscapeModel voronoi({"voronoi", 3, 1, 6});
  EXPECT_THROW(voronoi.trend({0.1, 0.2, 0.3}), base::UserError);
}

// fail_fraction: about that fraction of the box fails, in a region (not scattered points), and the
// features are the landscape's whether a trial fails or not.
TEST(LandscapeModel, FailFractionFailsAboutThatMuchOfTheBoxInARegion) {
  for (double fraction : {0.0, 0.3, 0.6}) {
    LandscapeOptions options{"plateaus", 3, 7, 6};
    const LandscapeModel plain(options);
    options.fail_fraction = fraction;
    const LandscapeModel model(options);
    base::Rng rng(11);
    int failed = 0, neighbours_agree = 0;
    for (int i = 0; i < 4000; ++i) {
      const std::vector<double> x = {rng.uniform(0.0, 0.98), rng.uniform(), rng.uniform()};
      const bool ok = model.succeeds(x);
      failed += ok ? 0 : 1;
      neighbours_agree += ok == model.succeeds({x[0] + 0.02, x[1], x[2]}) ? 1 : 0;
      EXPECT_EQ(model.feature(x), plain.feature(x));
    }
    EXPECT_NEAR(failed / 4000.0, fraction, 0.05) << fraction;
    EXPECT_GT(neighbours_agree, 3800) << fraction;  // a nearby point mostly shares the outcome
  }
  EXPECT_THROW(LandscapeModel({"plateaus", 3, 7, 6, 0.0, 1.0}), base::UserError);
}

// The task declares its success rule only where trials can fail, and reports each trial's success.
TEST(LandscapeTask, FailFractionDeclaresTheSuccessRule) {
  auto task = plugins::load_task("landscape");
  EXPECT_FALSE(task->describe(Json::object()).contains("success"));
  const Json described = task->describe({{"fail_fraction", 0.5}});
  EXPECT_EQ(described.at("success"), Json({{"info", "/success"}}));
  NullSink sink;
  int failed = 0;
  for (double x0 = 0.0; x0 <= 1.0; x0 += 0.1) {
    auto request = request_for({{"fail_fraction", 0.5}}, 1);
    request.params["x0"] = x0;
    const auto result = task->run(request, sink);
    failed += result.info.at("success").get<bool>() ? 0 : 1;
    EXPECT_EQ(result.features.size(), 2u);
  }
  EXPECT_GT(failed, 0);
}

}  // namespace
}  // namespace podium::tasks::landscape
