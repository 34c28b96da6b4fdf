#include "podium/store/store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <fstream>

#include "podium/base/error.h"
#include "process.h"

namespace podium::store {
namespace {

using podium::testing::TempDir;

std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

NewStage one_stage() {
  NewStage s;
  s.name = "explore";
  s.task = "landscape";
  s.algorithm = "random";
  s.description = {{"params", Json::array()}, {"features", Json::array()}};
  s.budget_trials = 10;
  return s;
}

TEST(Store, CreatesLatestSchemaInWalMode) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  EXPECT_EQ(store->schema_version(), Store::latest_schema_version());
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir / "p.db").c_str(), &db), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)), "wal");
  sqlite3_finalize(s);
  sqlite3_close(db);
}

TEST(Store, RefusesNewerSchemaWithoutTouchingTheFile) {
  TempDir dir;
  const auto path = dir / "newer.db";
  {
    sqlite3* db = nullptr;
    sqlite3_open(path.c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE schema_version (version INTEGER); INSERT INTO schema_version VALUES (99);", nullptr,
                 nullptr, nullptr);
    sqlite3_close(db);
  }
  const std::string before = file_bytes(path);
  try {
    Store::open(path, Store::Access::read_write);
    FAIL() << "expected an error";
  } catch (const base::RuntimeError& e) {
    EXPECT_TRUE(::testing::internal::RE::PartialMatch(e.what(), "schema version 99 is newer than this podium supports \\(2\\)"))
        << e.what();
  }
  EXPECT_EQ(file_bytes(path), before);
  EXPECT_FALSE(std::filesystem::exists(path.string() + "-wal"));
}

TEST(Store, RefusesForeignDatabase) {
  TempDir dir;
  const auto path = dir / "other.db";
  sqlite3* db = nullptr;
  sqlite3_open(path.c_str(), &db);
  sqlite3_exec(db, "CREATE TABLE customers (id INTEGER);", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  EXPECT_THROW(
      {
        try {
          Store::open(path, Store::Access::read_write);
        } catch (const base::RuntimeError& e) {
          EXPECT_NE(std::string(e.what()).find("not a Podium database"), std::string::npos) << e.what();
          throw;
        }
      },
      base::RuntimeError);
}

TEST(Store, UnwritablePathIsOneClearError) {
  EXPECT_THROW(
      {
        try {
          Store::open("/nonexistent-folder/p.db", Store::Access::read_write);
        } catch (const base::RuntimeError& e) {
          EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/p.db: cannot open database"), std::string::npos);
          throw;
        }
      },
      base::RuntimeError);
}

TEST(Store, TrialLifecycleRoundTrips) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto id = store->add_campaign("c", Json{{"name", "c"}}, 5, "", {one_stage()});
  const auto stages = store->stages(id);
  ASSERT_EQ(stages.size(), 1u);
  std::int64_t trial = 0;
  store->transaction([&] {
    trial = store->add_trial(stages[0].id, 0, Json{{"x0", 0.5}}, Json::object(), Json{{"step", "random"}}, 42);
    const auto attempt = store->start_attempt(trial, 1, "local:worker-1", "host");
    store->add_metrics(trial, {{"loss", 0, 1.0, 1}, {"loss", 1, 0.5, 1}});
    store->finish_attempt(attempt, "done", "", std::nullopt, std::nullopt);
    store->complete_trial(trial, {-0.25}, {"f0", "f1"}, {0.1, 0.2}, Json::object(), {{"policy", "/tmp/p.pt", "ab", 3}});
  });
  const auto trials = store->trials(stages[0].id);
  ASSERT_EQ(trials.size(), 1u);
  EXPECT_EQ(trials[0].state, "done");
  EXPECT_EQ(trials[0].seed, 42u);
  EXPECT_EQ(trials[0].features, (std::vector<double>{0.1, 0.2}));
  EXPECT_EQ(trials[0].objectives, Json({-0.25}));
  EXPECT_EQ(store->metrics(trial).size(), 2u);
  EXPECT_EQ(store->artifacts(trial).at(0).sha256, "ab");
  EXPECT_EQ(store->attempts(trial).at(0).state, "done");
  EXPECT_EQ(store->trial_counts(id).done, 1);
}

TEST(Store, TransactionRollsBackOnException) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto id = store->add_campaign("c", Json::object(), 1, "", {one_stage()});
  const auto stage = store->stages(id)[0].id;
  EXPECT_THROW(store->transaction([&] {
    store->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1);
    throw std::runtime_error("boom");
  }),
               std::runtime_error);
  EXPECT_TRUE(store->trials(stage).empty());
}

TEST(Store, DuplicateTrialIndexIsRejected) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto stage = store->stages(store->add_campaign("c", Json::object(), 1, "", {one_stage()}))[0].id;
  store->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1);
  EXPECT_THROW(store->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1), base::RuntimeError);
}

TEST(Store, RecoverMarksRunningAttemptsInterrupted) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto stage = store->stages(store->add_campaign("c", Json::object(), 1, "", {one_stage()}))[0].id;
  const auto trial = store->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1);
  store->start_attempt(trial, 1, "w", "h");
  EXPECT_EQ(store->recover_interrupted(), 1);
  EXPECT_EQ(store->trials(stage)[0].state, "interrupted");
  EXPECT_EQ(store->attempts(trial)[0].state, "interrupted");
}

TEST(Store, ReadOnlyOpenNeverCreatesAFile) {
  TempDir dir;
  EXPECT_THROW(Store::open(dir / "missing.db", Store::Access::read_only), base::RuntimeError);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing.db"));
}

}  // namespace
}  // namespace podium::store

namespace podium::store {
namespace {

// A database written by schema version 1 (tests/store/testdata/schema_v1.db: a 6-trial landscape
// campaign) migrates forward with its data intact and the v2 objective column filled in.
TEST(StoreMigration, SavedVersion1DatabaseMigratesToLatest) {
  podium::testing::TempDir dir;
  const auto path = dir / "v1.db";
  std::filesystem::copy_file(std::filesystem::path(PODIUM_STORE_TESTDATA) / "schema_v1.db", path);
  EXPECT_THROW(
      {
        try {
          Store::open(path, Store::Access::read_only);
        } catch (const base::RuntimeError& e) {
          EXPECT_NE(std::string(e.what()).find("schema version 1 is older than"), std::string::npos) << e.what();
          throw;
        }
      },
      base::RuntimeError);
  auto store = Store::open(path, Store::Access::read_write);
  EXPECT_EQ(store->schema_version(), Store::latest_schema_version());
  const auto campaigns = store->campaigns();
  ASSERT_EQ(campaigns.size(), 1u);
  EXPECT_EQ(campaigns[0].name, "saved-v1");
  const auto trials = store->campaign_trials(campaigns[0].id);
  ASSERT_EQ(trials.size(), 6u);
  for (const auto& t : trials) EXPECT_EQ(t.state, "done");

  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db, "SELECT count(*) FROM trials WHERE objective = json_extract(objectives, '$[0]')", -1, &s, nullptr);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(s, 0), 6);
  sqlite3_finalize(s);
  sqlite3_close(db);
}

}  // namespace
}  // namespace podium::store
