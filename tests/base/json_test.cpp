// Reading JSON files: every failure is one UserError line naming the file (and the position
// when the parser knows it).
#include "podium/base/json.h"

#include <gtest/gtest.h>

#include "podium/base/error.h"
#include "process.h"

namespace podium::base {
namespace {

std::string error_reading(const std::string& text) {
  testing::TempDir dir;
  testing::write_file(dir / "spec.json", text);
  try {
    read_json_file(dir / "spec.json");
  } catch (const UserError& e) {
    const std::string what = e.what();
    return what.substr(what.find("spec.json"));
  }
  return "(no error)";
}

TEST(ReadJsonFile, SyntaxErrorsGiveLineAndColumn) {
  EXPECT_EQ(error_reading("{\"a\": 1,\n \"b\": ,}").rfind("spec.json: invalid JSON at line 2 column", 0), 0u);
}

TEST(ReadJsonFile, ANumberBeyondDoubleRangeIsAUserError) {
  EXPECT_EQ(error_reading("{\"workers\": 1e400}"), "spec.json: invalid JSON: number overflow parsing '1e400'");
}

// A 60,000-deep array once crashed submit (stack overflow in nlohmann's recursive
// copies); depth is bounded at the read, with the position of the first bracket too deep.
TEST(ReadJsonFile, NestingDeeperThan100LevelsIsOneShortError) {
  const std::string deep = std::string(60000, '[') + std::string(60000, ']');
  EXPECT_EQ(error_reading(deep), "spec.json: invalid JSON at line 1 column 101: nested deeper than 100 levels");
  EXPECT_EQ(error_reading("{\"a\":\n" + std::string(101, '{')),
            "spec.json: invalid JSON at line 2 column 100: nested deeper than 100 levels");
  // 100 levels parse; brackets inside strings do not count.
  testing::TempDir dir;
  testing::write_file(dir / "ok.json", std::string(99, '[') + "{\"k\": \"[[[[\\\"{{{\"}" + std::string(99, ']'));
  EXPECT_EQ(read_json_file(dir / "ok.json")[0].size(), 1u);
}

}  // namespace
}  // namespace podium::base
