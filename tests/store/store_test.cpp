#include "podium/store/store.h"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "podium/base/error.h"
#include "process.h"

namespace podium::store {
namespace {

using podium::testing::file_bytes;
using podium::testing::TempDir;

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
    sqlite3_exec(db, "CREATE TABLE schema_version (version INTEGER); INSERT INTO schema_version VALUES (99);", nullptr, nullptr,
                 nullptr);
    sqlite3_close(db);
  }
  const std::string before = file_bytes(path);
  try {
    Store::open(path, Store::Access::read_write);
    FAIL() << "expected an error";
  } catch (const base::RuntimeError& e) {
    const std::string expected =
        "schema version 99 is newer than this podium supports (" + std::to_string(Store::latest_schema_version()) + ")";
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
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

// Features come back bit for bit (SQLite's JSON functions would print only 15 digits).
TEST(Store, FeaturesRoundTripAtFullPrecision) {
  TempDir dir;
  auto s = Store::open(dir / "f.db", Store::Access::read_write);
  const auto campaign = s->add_campaign("f", Json::object(), 1, "", {one_stage()});
  const auto stage = s->stages(campaign)[0].id;
  const auto t = s->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1);
  const std::vector<double> features = {0.1 + 0.2, 1.0 / 3.0, -2.718281828459045e-300};
  s->complete_trial(t, {1.0}, {"a", "b", "c"}, features, Json::object(), {});
  EXPECT_EQ(s->trials(stage)[0].features, features);
  EXPECT_EQ(s->campaign_trials(campaign)[0].features, features);
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

TEST(Store, StartStageStoresTheHandOverAndItsBudget) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  auto second = one_stage();
  second.name = "refine";
  second.inputs = {{"stages", {"explore"}}, {"select", "best"}, {"per_trial", "each"}};
  second.budget_trials = 0;
  const auto id = store->add_campaign("c", Json::object(), 1, "", {one_stage(), second});
  auto stages = store->stages(id);
  EXPECT_FALSE(stages[1].input_trials.has_value());
  const Json handed = Json::parse(R"([{"stage": "explore", "stage_index": 0, "trial_index": 3, "params": {"x0": 0.25},
      "objectives": [-0.5], "features": [0.1], "strategy": 0, "artifacts": {"policy": "/runs/p.pt"}}])");
  store->start_stage(stages[0].id, nullptr, 10);
  store->start_stage(stages[1].id, handed, 4);
  store->set_stage_state(stages[0].id, "failed", "all 10 trials failed");
  stages = store->stages(id);
  EXPECT_EQ(stages[1].state, "running");
  EXPECT_EQ(stages[1].input_trials, handed);
  EXPECT_EQ(stages[1].budget_trials, 4);
  EXPECT_EQ(stages[1].inputs, second.inputs);
  EXPECT_FALSE(stages[0].input_trials.has_value());
  EXPECT_EQ(stages[0].state, "failed");
  EXPECT_EQ(stages[0].error, "all 10 trials failed");
}

// A resumed attempt re-sends the steps since its checkpoint: each (name, step) is stored once,
// with the value first sent.
TEST(Store, MetricPointsAStepAlreadyHasAreDropped) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto stage = store->stages(store->add_campaign("c", Json::object(), 1, "", {one_stage()}))[0].id;
  const auto trial = store->add_trial(stage, 0, Json::object(), Json::object(), Json::object(), 1);
  const auto other = store->add_trial(stage, 1, Json::object(), Json::object(), Json::object(), 1);
  store->add_metrics(trial, {{"loss", 0, 1.0, 1}, {"loss", 1, 0.5, 1}, {"return", 1, 7.0, 1}});
  store->add_metrics(trial, {{"loss", 1, 0.6, 2}, {"loss", 2, 0.4, 2}, {"return", 2, 8.0, 2}});
  store->add_metrics(other, {{"loss", 1, 0.9, 1}});
  const auto points = store->metrics(trial);
  ASSERT_EQ(points.size(), 5u);
  EXPECT_EQ(points[1].step, 1);
  EXPECT_EQ(points[1].value, 0.5);
  EXPECT_EQ(points[1].attempt, 1);
  EXPECT_EQ(points[2].step, 2);
  EXPECT_EQ(points[2].attempt, 2);
  EXPECT_EQ(store->metrics(other).size(), 1u);
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

// The rows of a query as text, one "a|b|c" line per row.
std::string rows(const std::filesystem::path& path, const char* sql) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::string out;
  if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK) out = std::string("error: ") + sqlite3_errmsg(db);
  while (s && sqlite3_step(s) == SQLITE_ROW) {
    for (int c = 0; c < sqlite3_column_count(s); ++c) {
      const auto* text = sqlite3_column_text(s, c);
      out += (c ? "|" : "") + std::string(text ? reinterpret_cast<const char*>(text) : "NULL");
    }
    out += "\n";
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return out;
}

// The counts the v3 triggers keep must equal a recount of the trials.
void expect_counts_equal_recount(const std::filesystem::path& path) {
  EXPECT_EQ(rows(path, "SELECT stage_id, state, trials FROM stage_state_counts WHERE trials > 0 ORDER BY 1, 2"),
            rows(path, "SELECT stage_id, state, count(*) FROM trials GROUP BY 1, 2 ORDER BY 1, 2"));
  EXPECT_EQ(rows(path, "SELECT stage_id, strategy, trials FROM stage_strategy_counts WHERE trials > 0 ORDER BY 1, 2"),
            rows(path,
                 "SELECT stage_id, strategy, count(*) FROM trials WHERE strategy IS NOT NULL GROUP BY 1, 2 "
                 "ORDER BY 1, 2"));
  EXPECT_EQ(rows(path, "SELECT count(*) FROM stage_state_counts WHERE trials < 0"), "0\n");
  EXPECT_EQ(rows(path, "SELECT count(*) FROM stage_strategy_counts WHERE trials < 0"), "0\n");
}

// Saved databases of older schemas (tests/store/testdata): schema_v1.db, a 6-trial landscape
// campaign; schema_v2.db, a two-stage landscape campaign with a retried trial, a failed one and
// strategies. Each migrates forward with its data intact, the v2 objective column filled in and
// the v3 count rows equal to a recount.
void expect_migrates(const char* file, int version, const std::string& name, std::size_t trials) {
  podium::testing::TempDir dir;
  const auto path = dir / file;
  std::filesystem::copy_file(std::filesystem::path(PODIUM_STORE_TESTDATA) / file, path);
  EXPECT_THROW(
      {
        try {
          Store::open(path, Store::Access::read_only);
        } catch (const base::RuntimeError& e) {
          const std::string expected = "schema version " + std::to_string(version) + " is older than";
          EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
          throw;
        }
      },
      base::RuntimeError);
  auto store = Store::open(path, Store::Access::read_write);
  EXPECT_EQ(store->schema_version(), Store::latest_schema_version());
  const auto campaigns = store->campaigns();
  ASSERT_EQ(campaigns.size(), 1u);
  EXPECT_EQ(campaigns[0].name, name);
  const auto all = store->campaign_trials(campaigns[0].id);
  ASSERT_EQ(all.size(), trials);
  EXPECT_EQ(rows(path, "SELECT count(*) FROM trials WHERE objective IS NOT json_extract(objectives, '$[0]')"), "0\n");
  expect_counts_equal_recount(path);
  const auto counts = store->trial_counts(campaigns[0].id);
  EXPECT_EQ(counts.total, static_cast<std::int64_t>(trials));
  EXPECT_EQ(counts.done, std::count_if(all.begin(), all.end(), [](const auto& t) { return t.state == "done"; }));
}

TEST(StoreMigration, SavedVersion1DatabaseMigratesToLatest) { expect_migrates("schema_v1.db", 1, "saved-v1", 6); }

// schema_v3.db: a two-stage landscape campaign ("refine" took explore's best trial as input)
// with a retried trial and a failed one, saved before stages stored their hand-over.
TEST(StoreMigration, SavedVersion3DatabaseMigratesToLatest) {
  expect_migrates("schema_v3.db", 3, "saved-v3", 9);
  podium::testing::TempDir dir;
  std::filesystem::copy_file(std::filesystem::path(PODIUM_STORE_TESTDATA) / "schema_v3.db", dir / "v3.db");
  auto store = Store::open(dir / "v3.db", Store::Access::read_write);
  const auto stages = store->stages(store->campaigns().at(0).id);
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[1].inputs, Json::parse(R"({"stage": "explore", "select": "best"})"));
  for (const auto& st : stages) {
    EXPECT_EQ(st.state, "done");
    EXPECT_FALSE(st.input_trials.has_value());
    EXPECT_EQ(st.error, "");
    // v5: schedulers before it told every finished trial (done, failed or cancelled) at once.
    EXPECT_EQ(st.told, store->stage_trial_counts(st.id).done + store->stage_trial_counts(st.id).failed +
                           store->stage_trial_counts(st.id).cancelled);
  }
}

// The indexes a schema-v6 database has beyond v5's (and v5's metrics_by_trial, which v6 replaces).
std::string v6_indexes(const std::filesystem::path& path) {
  return rows(path,
              "SELECT name FROM sqlite_master WHERE type = 'index' AND name IN ('metrics_by_series', "
              "'trials_by_strategy_finish', 'artifacts_by_trial', 'events_by_campaign', 'metrics_by_trial') ORDER BY name");
}

// Strategy labels as a walk of the stage's done trials in finishing order (finished_at, idx)
// numbers them: what Store::strategy_labels must give.
StrategyLabels labels_by_walk(const std::filesystem::path& path, std::int64_t stage_id) {
  const std::string sql = "SELECT strategy FROM trials WHERE stage_id = " + std::to_string(stage_id) +
                          " AND state = 'done' AND strategy IS NOT NULL ORDER BY finished_at, idx";
  StrategyLabels labels;
  std::istringstream lines(rows(path, sql.c_str()));
  for (std::string line; std::getline(lines, line);)
    labels.emplace(std::stoll(line), static_cast<std::int64_t>(labels.size()) + 1);
  return labels;
}

// schema_v5.db: a two-stage campaign written by the v5 store, with failed trials, strategies,
// features, two artifacts per done trial, metric series (two names, a NaN, a second attempt) and
// events. v6 adds indexes only: every row reads back the same, the typed reads agree, and the
// migration runs again harmlessly (a database whose version says 5 but has the v6 indexes).
TEST(StoreMigration, SavedVersion5DatabaseMigratesToLatestWithItsRowsUnchanged) {
  expect_migrates("schema_v5.db", 5, "saved-v5", 11);
  const auto saved = std::filesystem::path(PODIUM_STORE_TESTDATA) / "schema_v5.db";
  TempDir dir;
  const auto path = dir / "v5.db";
  std::filesystem::copy_file(saved, path);
  EXPECT_EQ(v6_indexes(path), "metrics_by_trial\n");
  const char* contents[] = {"SELECT * FROM metrics ORDER BY rowid", "SELECT * FROM artifacts ORDER BY id",
                            "SELECT * FROM events ORDER BY id", "SELECT * FROM trials ORDER BY id",
                            "SELECT * FROM features ORDER BY trial_id, idx"};
  std::vector<std::string> before;
  for (const char* sql : contents) before.push_back(rows(path, sql));
  EXPECT_NE(before[0], "");
  {
    auto store = Store::open(path, Store::Access::read_write);
    EXPECT_EQ(store->schema_version(), 6);
  }
  const std::string indexes = "artifacts_by_trial\nevents_by_campaign\nmetrics_by_series\ntrials_by_strategy_finish\n";
  EXPECT_EQ(v6_indexes(path), indexes);
  for (std::size_t i = 0; i < std::size(contents); ++i) EXPECT_EQ(rows(path, contents[i]), before[i]) << contents[i];
  const std::string schema = rows(path, "SELECT type, name, sql FROM sqlite_master ORDER BY name");
  // Again from version 5 on a database that already has the v6 indexes: no error, same schema.
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(db, "UPDATE schema_version SET version = 5", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  auto store = Store::open(path, Store::Access::read_write);
  EXPECT_EQ(store->schema_version(), 6);
  EXPECT_EQ(rows(path, "SELECT type, name, sql FROM sqlite_master ORDER BY name"), schema);
  for (std::size_t i = 0; i < std::size(contents); ++i) EXPECT_EQ(rows(path, contents[i]), before[i]) << contents[i];
  // The typed reads through the new indexes.
  const auto campaign = store->campaigns().at(0).id;
  const auto stages = store->stages(campaign);
  ASSERT_EQ(stages.size(), 2u);
  for (const auto& st : stages) EXPECT_EQ(store->strategy_labels(st.id), labels_by_walk(path, st.id));
  EXPECT_EQ(store->strategy_labels(stages[0].id), (StrategyLabels{{0, 1}, {1, 2}, {2, 3}}));
  EXPECT_EQ(store->events(campaign).size(), 4u);  // started, two trials failed, done
  const auto trials = store->trials(stages[0].id);
  EXPECT_EQ(store->artifacts(trials[0].id).size(), 2u);
  EXPECT_EQ(store->artifacts(trials[3].id).size(), 0u);  // failed
  const auto points = store->metrics(trials[5].id);
  EXPECT_EQ(points.size(), 12u);  // return 0..5 (attempt 1), 6..8 (attempt 2), loss x3
  EXPECT_EQ(std::count_if(points.begin(), points.end(), [](const MetricPoint& p) { return p.attempt == 2; }), 3);
}

// Labels are the order strategies were first found, however late in the stage: a strategy found
// by the last trial to finish, one whose only trials failed (no label), ties on the finishing
// time broken by the lower index.
TEST(Store, StrategyLabelsFollowTheFirstDoneTrialOfEachStrategy) {
  TempDir dir;
  const auto path = dir / "l.db";
  auto store = Store::open(path, Store::Access::read_write);
  const auto stage = store->stages(store->add_campaign("c", Json::object(), 1, "", {one_stage()}))[0].id;
  std::vector<std::int64_t> t;
  store->transaction([&] {
    for (int i = 0; i < 40; ++i) t.push_back(store->add_trial(stage, i, Json::object(), Json::object(), Json::object(), 1));
  });
  EXPECT_TRUE(store->strategy_labels(stage).empty());
  store->transaction([&] {
    for (int i = 39; i >= 0; --i) {  // finish in reverse index order
      if (i == 7) {
        store->set_trial_state(t[i], "failed", "boom");
        store->set_trial_strategy(t[i], 99);  // a strategy with no done trial
        continue;
      }
      store->complete_trial(t[i], {double(i)}, {}, {}, Json::object(), {});
      store->set_trial_strategy(t[i], i == 0 ? 5 : i % 4);  // strategy 5: only the last trial to finish
    }
  });
  {
    sqlite3* db = nullptr;
    // Finishing times made exact: reverse index order, but trials 10, 20 and 21 first and together.
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(db,
                           "UPDATE trials SET finished_at = 2e9 - idx; "
                           "UPDATE trials SET finished_at = 1e9 WHERE idx IN (10, 20, 21)",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  const auto labels = store->strategy_labels(stage);
  EXPECT_EQ(labels, labels_by_walk(path, stage));
  // Trials 10, 20, 21 (strategies 2, 0, 1) in index order, then 39 (strategy 3), ..., then 0.
  EXPECT_EQ(labels, (StrategyLabels{{2, 1}, {0, 2}, {1, 3}, {3, 4}, {5, 5}}));
}

TEST(Store, SearchStateIsSavedWithHowManyTrialsWereTold) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto id = store->add_campaign("c", Json::object(), 1, "", {one_stage()});
  const auto stage = store->stages(id).at(0).id;
  EXPECT_EQ(store->stages(id).at(0).told, 0);
  store->save_search_state(stage, {{"k", 1}}, 2.5, 7);
  const auto st = store->stages(id).at(0);
  EXPECT_EQ(st.told, 7);
  EXPECT_EQ(*st.search_state, Json({{"k", 1}}));
}

TEST(StoreMigration, SavedVersion2DatabaseMigratesToLatest) {
  expect_migrates("schema_v2.db", 2, "saved-v2", 11);
  EXPECT_EQ(
      rows(std::filesystem::path(PODIUM_STORE_TESTDATA) / "schema_v2.db", "SELECT state, count(*) FROM trials GROUP BY state"),
      "done|10\nfailed|1\n");  // the saved file itself is untouched (copied first)
}

// Every way the scheduler changes trials (retries, failures, cancel, interruption and recovery,
// strategies assigned and regrouped) keeps the count rows equal to a recount, and
// trial_counts() reads them.
TEST(StoreCounts, CountRowsEqualARecountThroughTheTrialLifecycle) {
  TempDir dir;
  const auto path = dir / "c.db";
  auto s = Store::open(path, Store::Access::read_write);
  auto second = one_stage();
  second.name = "refine";
  const auto campaign = s->add_campaign("c", Json::object(), 1, "", {one_stage(), second});
  const auto stages = s->stages(campaign);
  std::vector<std::int64_t> t;
  s->transaction([&] {
    for (int i = 0; i < 12; ++i)
      t.push_back(s->add_trial(stages[i / 8].id, i % 8, Json::object(), Json::object(), Json::object(), 1));
  });
  const auto finish = [&](std::int64_t trial, int attempt, const char* outcome) {
    const auto a = s->start_attempt(trial, attempt, "w", "h");
    if (std::string(outcome) == "done") {
      s->finish_attempt(a, "done", "", std::nullopt, std::nullopt);
      s->complete_trial(trial, {double(trial)}, {"f"}, {0.5}, Json::object(), {});
    } else {
      s->finish_attempt(a, "failed", "boom", 1, std::nullopt);
      s->set_trial_state(trial, outcome, "boom");
    }
  };
  s->transaction([&] {
    finish(t[0], 1, "done");
    finish(t[1], 1, "pending");  // retried, then done
    finish(t[1], 2, "done");
    finish(t[2], 1, "pending");  // retried, then failed
    finish(t[2], 2, "failed");
    finish(t[3], 1, "done");
    finish(t[8], 1, "done");
    s->start_attempt(t[4], 1, "w", "h");  // left running: the scheduler dies
    s->start_attempt(t[9], 1, "w", "h");
    s->set_trial_strategy(t[0], 0);
    s->set_trial_strategy(t[1], 1);
    s->set_trial_strategy(t[3], 1);
    s->set_trial_strategy(t[8], 0);
  });
  expect_counts_equal_recount(path);
  EXPECT_EQ(s->recover_interrupted(), 2);
  expect_counts_equal_recount(path);
  s->transaction([&] {
    finish(t[4], 2, "done");  // interrupted, run again
    for (int i : {5, 6, 10}) s->set_trial_state(t[i], "cancelled", "campaign cancelled");
    s->set_trial_strategy(t[4], 2);
    s->set_trial_strategy(t[1], 0);  // regrouped when the stage ends
    s->set_trial_strategy(t[3], 0);  // strategy 1 is empty now
  });
  expect_counts_equal_recount(path);
  const auto c = s->trial_counts(campaign);
  EXPECT_EQ(c.total, 12);
  EXPECT_EQ(c.done, 5);
  EXPECT_EQ(c.failed, 1);
  EXPECT_EQ(c.cancelled, 3);
  EXPECT_EQ(c.interrupted, 1);  // t[9]
  EXPECT_EQ(c.pending, 2);      // t[7], t[11]
  EXPECT_EQ(s->stage_trial_counts(stages[1].id).total, 4);
  EXPECT_EQ(rows(path, "SELECT strategy, trials FROM stage_strategy_counts WHERE stage_id = 1 ORDER BY 1"), "0|3\n1|0\n2|1\n");
}

// What a campaign summary reads: a stage's done trials in index order with their primary
// objective, strategy and finish time, and the result info only of those that give a table.
TEST(Store, DoneTrialsAreLeanAndInIndexOrder) {
  TempDir dir;
  auto store = Store::open(dir / "p.db", Store::Access::read_write);
  const auto stage = store->stages(store->add_campaign("c", Json::object(), 1, "", {one_stage()}))[0].id;
  std::vector<std::int64_t> ids;
  store->transaction([&] {
    for (int i = 0; i < 4; ++i) ids.push_back(store->add_trial(stage, i, Json::object(), Json::object(), Json::object(), i));
    store->complete_trial(ids[2], {0.5, 2.0}, {"f0"}, {0.25}, Json{{"table", {{"rows", Json::array()}}}}, {});
    store->complete_trial(ids[0], {-1.0}, {"f0"}, {0.75}, Json{{"note", "no table"}}, {});
    store->set_trial_strategy(ids[2], 3);
    store->set_trial_state(ids[1], "failed", "boom");
  });
  const auto done = store->done_trials(stage);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(done[0].index, 0);
  EXPECT_EQ(done[0].objective, -1.0);
  EXPECT_FALSE(done[0].strategy);
  EXPECT_EQ(done[0].result_info, "");
  EXPECT_EQ(done[1].id, ids[2]);
  EXPECT_EQ(done[1].objective, 0.5);
  EXPECT_EQ(done[1].strategy, 3);
  EXPECT_GT(done[1].finished_at, 0.0);
  EXPECT_EQ(Json::parse(done[1].result_info), (Json{{"table", {{"rows", Json::array()}}}}));
  const auto one = store->trial(ids[2]);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->features, std::vector<double>{0.25});
  EXPECT_EQ(one->objectives, Json({0.5, 2.0}));
  EXPECT_FALSE(store->trial(ids.back() + 100));
}

}  // namespace
}  // namespace podium::store
