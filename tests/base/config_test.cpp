// The one config reader: typed reads, ranges, enums, unknown keys, nested paths in errors, and the
// description a describing reader records (what `podium tasks` shows).
#include "podium/base/config.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace podium::base {
namespace {

struct Rule {
  std::string mode;
  std::vector<int> trials;
};

struct Options {
  std::string family;
  int dim = 0;
  double noise = 0;
  bool artifact = false;
  std::uint64_t seed = 0;
  std::vector<Rule> rules;
  double gain = 0;
};

// A config shaped like a task's: scalars with ranges, an enum, an array of objects, a nested object.
Options read_options(ConfigReader& r) {
  Options o;
  o.family = r.choice("family", "basins", {"basins", "plateaus", "voronoi"}, "landscape family");
  o.dim = r.integer("dim", 3, {1, 64}, "parameter dimension");
  o.noise = r.number("noise", 0.0, {.min = 0.0});
  o.artifact = r.boolean("artifact", false);
  o.seed = r.integer<std::uint64_t>("seed", 1);
  o.rules = r.objects("failures", [](ConfigReader& f) {
    return Rule{f.choice("mode", required, {"throw", "hang"}), f.integers<int>("trials", {}, {.min = 0})};
  });
  o.gain = r.object("pd", [](ConfigReader& pd) { return pd.number("kp", 1.0, {.min = 0.0, .exclusive_min = true}); });
  return o;
}

Options read(const Json& config) {
  ConfigReader r(config, "", "task config");
  Options o = read_options(r);
  r.finish();
  return o;
}

std::string error_of(const Json& config) {
  try {
    read(config);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ConfigReader, AbsentKeysGiveDefaultsAndPresentOnesTheirValues) {
  const Options d = read(Json::object());
  EXPECT_EQ(d.family, "basins");
  EXPECT_EQ(d.dim, 3);
  EXPECT_EQ(d.seed, 1u);
  EXPECT_TRUE(d.rules.empty());
  EXPECT_EQ(d.gain, 1.0);

  const Options o = read(Json::parse(R"({"family": "voronoi", "dim": 64, "noise": 0.5, "artifact": true,
      "seed": 9223372036854775807, "failures": [{"mode": "hang", "trials": [0, 3]}], "pd": {"kp": 2}})"));
  EXPECT_EQ(o.family, "voronoi");
  EXPECT_EQ(o.dim, 64);
  EXPECT_EQ(o.noise, 0.5);
  EXPECT_TRUE(o.artifact);
  EXPECT_EQ(o.seed, 9223372036854775807u);
  ASSERT_EQ(o.rules.size(), 1u);
  EXPECT_EQ(o.rules[0].mode, "hang");
  EXPECT_EQ(o.rules[0].trials, (std::vector<int>{0, 3}));
  EXPECT_EQ(o.gain, 2.0);
}

TEST(ConfigReader, UnsignedAboveInt64IsOutOfRangeNotWrapped) {
  // Integers are int64 inside the reader: a larger unsigned value is refused, not wrapped.
  EXPECT_EQ(error_of({{"seed", 18446744073709551615ull}}),
            "task config: seed: 18446744073709551615 is not in [0, 9223372036854775807]");
  EXPECT_EQ(error_of({{"seed", -1}}), "task config: seed: -1 is not >= 0");
}

TEST(ConfigReader, WrongTypesNameThePathAndTheType) {
  EXPECT_EQ(error_of({{"noise", "abc"}}), "task config: noise: \"abc\" is not a number");
  EXPECT_EQ(error_of({{"dim", 2.5}}), "task config: dim: 2.5 is not an integer");
  EXPECT_EQ(error_of({{"artifact", 1}}), "task config: artifact: 1 is not a boolean (true or false)");
  EXPECT_EQ(error_of({{"pd", 3}}), "task config: pd: 3 is not an object");
  EXPECT_EQ(error_of({{"failures", "all"}}), "task config: failures: \"all\" is not an array of objects");
  EXPECT_EQ(error_of(Json::array()), "task config: [] is not an object");
}

TEST(ConfigReader, RangesAreCheckedWithTheirRule) {
  EXPECT_EQ(error_of({{"dim", 0}}), "task config: dim: 0 is not in [1, 64]");
  EXPECT_EQ(error_of({{"dim", 1000000000000}}), "task config: dim: 1000000000000 is not in [1, 64]");
  EXPECT_EQ(error_of({{"noise", -0.1}}), "task config: noise: -0.1 is not >= 0");
  EXPECT_EQ(error_of({{"pd", {{"kp", 0}}}}), "task config: pd.kp: 0 is not > 0");
  EXPECT_EQ(read({{"dim", 1}}).dim, 1);
  EXPECT_EQ(read({{"dim", 64}}).dim, 64);
}

TEST(ConfigReader, IntegerRangeIsClampedToTheResultType) {
  const Json spec = {{"workers", 4294967297}};
  ConfigReader r(spec, "", "spec.json");
  EXPECT_THROW(
      try { r.integer("workers", 2, {.min = 1}); } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "spec.json: workers: 4294967297 is not in [1, 2147483647]");
        throw;
      },
      ConfigError);
}

TEST(ConfigReader, EnumsListWhatIsAllowed) {
  EXPECT_EQ(error_of({{"family", "plateus"}}), "task config: family: \"plateus\" is not one of basins, plateaus, voronoi");
  EXPECT_EQ(error_of({{"family", 3}}), "task config: family: 3 is not one of basins, plateaus, voronoi");
}

TEST(ConfigReader, UnknownKeysAreRejectedWithTheKnownOnes) {
  EXPECT_EQ(error_of({{"dimm", 3}}), "task config: dimm: unknown key (known: artifact, dim, failures, family, noise, pd, seed)");
  EXPECT_EQ(error_of({{"pd", {{"kd", 1}}}}), "task config: pd.kd: unknown key (known: kp)");
}

TEST(ConfigReader, NestedErrorsCarryTheWholeJsonPath) {
  EXPECT_EQ(error_of(Json::parse(R"({"failures": [{"mode": "throw"}, {"mode": "explode"}]})")),
            "task config: failures[1].mode: \"explode\" is not one of throw, hang");
  EXPECT_EQ(error_of(Json::parse(R"({"failures": [{"trials": [1]}]})")), "task config: failures[0].mode: missing (required)");
  EXPECT_EQ(error_of(Json::parse(R"({"failures": [{"mode": "throw", "trials": "all"}]})")),
            "task config: failures[0].trials: \"all\" is not an array of integers in [0, 2147483647]");
  EXPECT_EQ(error_of(Json::parse(R"({"failures": [{"mode": "throw", "trials": [2, -1]}]})")),
            "task config: failures[0].trials[1]: -1 is not in [0, 2147483647]");
  EXPECT_EQ(error_of(Json::parse(R"({"failures": [{"mode": "throw", "trial": [2]}]})")),
            "task config: failures[0].trial: unknown key (known: mode, trials)");
}

TEST(ConfigReader, ErrorsExposePathAndProblemSeparately) {
  const Json config = {{"dim", 0}};
  ConfigReader r(config, "stages[0].config");
  try {
    r.integer("dim", 3, {1, 64});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.path(), "stages[0].config.dim");
    EXPECT_EQ(e.problem(), "0 is not in [1, 64]");
    EXPECT_STREQ(e.what(), "stages[0].config.dim: 0 is not in [1, 64]");
  }
}

TEST(ConfigReader, LongValuesAreCutShortInErrors) {
  const std::string error = error_of({{"noise", std::string(5000, 'x')}});
  EXPECT_LT(error.size(), 200u) << error;
  EXPECT_NE(error.find("xxx... is not a number"), std::string::npos) << error;
}

TEST(ConfigReader, CustomRulesFailWithTheSameShape) {
  const Json stage = {{"name", "a"}}, unnamed = {{"name", ""}};
  ConfigReader r(stage, "stages[1]", "spec.json");
  r.string("name", required);
  try {
    r.fail("name", "is already the name of an earlier stage");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "spec.json: stages[1].name: \"a\" is already the name of an earlier stage");
  }
  ConfigReader empty(unnamed, "", "spec.json");
  EXPECT_THROW(empty.string("name", required), ConfigError);
  EXPECT_FALSE(empty.has("other"));
}

TEST(ConfigReader, AnExistingFileMustNameARegularFile) {
  const std::string here = std::filesystem::temp_directory_path().string();
  const Json config = {{"empty", ""}, {"folder", here}, {"missing", here + "/no such checkpoint"}};
  ConfigReader r(config, "stages[0].config", "spec.json");
  EXPECT_EQ(r.existing_file("empty", "x"), "");
  EXPECT_EQ(r.existing_file("absent", ""), "");
  for (const char* key : {"folder", "missing"}) {
    try {
      r.existing_file(key, "");
      FAIL() << key << ": no error";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.path(), std::string("stages[0].config.") + key);
      EXPECT_NE(e.problem().find("is not a file"), std::string::npos) << e.what();
    }
  }
}

TEST(ConfigReader, DescribeRecordsEveryKeyFromTheReadingCode) {
  const Json d = ConfigReader::describe(read_options);
  ASSERT_EQ(d.size(), 7u) << d.dump(2);
  EXPECT_EQ(d[0], Json::parse(R"({"key": "family", "type": "string", "default": "basins",
                                  "choices": ["basins", "plateaus", "voronoi"], "doc": "landscape family"})"));
  EXPECT_EQ(d[1], Json::parse(R"({"key": "dim", "type": "integer", "default": 3, "min": 1, "max": 64,
                                  "doc": "parameter dimension"})"));
  EXPECT_EQ(d[2], Json::parse(R"({"key": "noise", "type": "number", "default": 0.0, "min": 0.0})"));
  EXPECT_EQ(d[3], Json::parse(R"({"key": "artifact", "type": "boolean", "default": false})"));
  EXPECT_EQ(d[4], Json::parse(R"({"key": "seed", "type": "integer", "default": 1, "min": 0})"));
  EXPECT_EQ(d[5], Json::parse(R"({"key": "failures", "type": "array", "default": [], "items": {"type": "object", "keys": [
      {"key": "mode", "type": "string", "required": true, "choices": ["throw", "hang"]},
      {"key": "trials", "type": "array", "default": [], "items": {"type": "integer", "min": 0, "max": 2147483647}}]}})"));
  EXPECT_EQ(d[6], Json::parse(R"({"key": "pd", "type": "object", "keys": [
      {"key": "kp", "type": "number", "default": 1.0, "min": 0.0, "exclusive_min": true}]})"));
}

TEST(ConfigReader, DefaultsComeFromTheDescription) {
  EXPECT_EQ(ConfigReader::defaults(ConfigReader::describe(read_options)),
            Json::parse(R"({"family": "basins", "dim": 3, "noise": 0.0, "artifact": false, "seed": 1,
                            "failures": [], "pd": {"kp": 1.0}})"));
}

TEST(ConfigReader, ReadingAlsoDescribesWhatWasRead) {
  const Json config = Json::parse(R"({"dim": 5, "failures": [{"mode": "throw"}, {"mode": "hang", "trials": [1]}]})");
  ConfigReader r(config, "");
  EXPECT_EQ(read_options(r).rules.size(), 2u);
  EXPECT_EQ(r.description(), ConfigReader::describe(read_options));
}

// A reader that collects into a container runs once per element, never on a describing one.
TEST(ConfigReader, VoidElementReadersRunOncePerElement) {
  const Json config = Json::parse(R"({"stages": [{"name": "a"}, {"name": "b"}], "none": []})");
  ConfigReader r(config, "", "spec.json");
  std::vector<std::string> names;
  r.objects("stages", [&](ConfigReader& stage) { names.push_back(stage.string("name", required)); });
  r.objects("none", [&](ConfigReader& stage) { names.push_back(stage.string("name", required)); });
  r.finish();
  EXPECT_EQ(names, (std::vector<std::string>{"a", "b"}));
}

struct PlainConfig {
  std::vector<int> hidden = {64, 64};
  std::string activation = "tanh";
  std::int64_t steps = 100;
  double lr = 1e-3;
  bool normalize = true;
};

TEST(ConfigReader, FieldReadsAPlainStructByItsTypes) {
  PlainConfig c;
  const Json config = Json::parse(R"({"hidden": [8], "steps": 7, "normalize": false})");
  ConfigReader r(config, "", "ppo config");
  r.field("hidden", c.hidden);
  r.field("activation", c.activation);
  r.field("steps", c.steps);
  r.field("lr", c.lr);
  r.field("normalize", c.normalize);
  r.finish();
  EXPECT_EQ(c.hidden, std::vector<int>{8});
  EXPECT_EQ(c.activation, "tanh");
  EXPECT_EQ(c.steps, 7);
  EXPECT_FALSE(c.normalize);

  const Json wide = {{"hidden", {8, "wide"}}};
  ConfigReader bad(wide, "", "ppo config");
  EXPECT_THROW(
      try { bad.field("hidden", c.hidden); } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "ppo config: hidden[1]: \"wide\" is not an integer");
        throw;
      },
      ConfigError);
}

}  // namespace
}  // namespace podium::base
