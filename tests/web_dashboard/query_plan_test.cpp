// The SQL behind the campaign page and the metric plot, as the server runs it: a trace on every
// SQLite connection this process opens collects each statement a request runs, and SQLite's
// EXPLAIN QUERY PLAN shows how it reads. None scans a trial-sized table or sorts rows in a
// temporary b-tree (the cost would grow with the campaign, whatever the page shows), and a metric
// series is read from an index alone. Plans do not depend on the row counts here (the store keeps
// no ANALYZE statistics), so a small campaign shows what a 100,000-trial one runs.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "dashboard_support.h"
#include "podium/store/store.h"

namespace podium::web_dashboard {
namespace {

using base::Json;

// The statements every traced connection ran (their SQL text, parameters unexpanded).
struct Trace {
  std::mutex mutex;
  std::set<std::string> statements;
};
Trace& trace() {
  static Trace t;
  return t;
}

int on_statement(unsigned type, void*, void* statement, void*) {
  if (type != SQLITE_TRACE_STMT) return 0;
  if (const char* sql = sqlite3_sql(static_cast<sqlite3_stmt*>(statement))) {
    std::lock_guard lock(trace().mutex);
    trace().statements.insert(sql);
  }
  return 0;
}

// An SQLite auto-extension: runs on every connection opened after it is registered.
int install_trace(sqlite3* db, char**, const sqlite3_api_routines*) {
  sqlite3_trace_v2(db, SQLITE_TRACE_STMT, on_statement, nullptr);
  return SQLITE_OK;
}

// What the server's SQLite connections ran while it answered `paths`, in an in-process server
// opened after the trace was installed.
std::set<std::string> statements_of(const std::filesystem::path& db, const std::vector<std::string>& paths) {
  sqlite3_auto_extension(reinterpret_cast<void (*)()>(&install_trace));
  {
    std::lock_guard lock(trace().mutex);
    trace().statements.clear();
  }
  {
    testing::RunningServer server(db);
    for (const auto& path : paths) {
      int status = 0;
      server.get_json(path, &status);
      EXPECT_EQ(status, 200) << path;
    }
  }
  sqlite3_cancel_auto_extension(reinterpret_cast<void (*)()>(&install_trace));
  std::lock_guard lock(trace().mutex);
  return trace().statements;
}

// EXPLAIN QUERY PLAN's lines for one statement, on a connection of our own.
std::vector<std::string> plan_of(const std::filesystem::path& db, const std::string& sql) {
  sqlite3* connection = nullptr;
  sqlite3_open_v2(db.c_str(), &connection, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* s = nullptr;
  std::vector<std::string> lines;
  if (sqlite3_prepare_v2(connection, ("EXPLAIN QUERY PLAN " + sql).c_str(), -1, &s, nullptr) != SQLITE_OK)
    lines.push_back(std::string("cannot explain: ") + sqlite3_errmsg(connection));
  while (s && sqlite3_step(s) == SQLITE_ROW) lines.emplace_back(reinterpret_cast<const char*>(sqlite3_column_text(s, 3)));
  sqlite3_finalize(s);
  sqlite3_close(connection);
  return lines;
}

// The queries among the statements (not BEGIN, COMMIT or PRAGMA), each with its plan.
std::vector<std::pair<std::string, std::vector<std::string>>> query_plans(const std::filesystem::path& db,
                                                                          const std::set<std::string>& statements) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& sql : statements)
    if (sql.rfind("SELECT", 0) == 0) out.emplace_back(sql, plan_of(db, sql));
  return out;
}

// A plan line that grows with the trials: a full scan of any table but the schema's own rows,
// the one-row schema_version and the campaign list (a subquery's rows are scanned as its own
// plan lines read them), or a sort in a temporary b-tree.
bool grows_with_trials(const std::string& line) {
  static const std::regex allowed_scan(
      "SCAN (CONSTANT ROW|sqlite_master|sqlite_schema|schema_version|campaigns|\\(subquery-[0-9]+\\))( .*)?");
  if (line.find("TEMP B-TREE") != std::string::npos) return true;
  return line.rfind("SCAN ", 0) == 0 && !std::regex_match(line, allowed_scan);
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "\n    " + l;
  return out;
}

// Two stages (300 and 40 trials; a failed trial every 25th), strategies, features, two artifacts
// per done trial, events, and two metric series on one trial (two attempts, a NaN).
std::filesystem::path build_campaign(const std::filesystem::path& dir) {
  auto db = dir / "plans.db";
  auto store = store::Store::open(db, store::Store::Access::read_write);
  store::NewStage a{"explore", "landscape", "bds"}, b{"refine", "landscape", "random"};
  a.description = b.description = {{"features", {{{"name", "f0"}}, {{"name", "f1"}}}}, {"objectives", {"objective"}}};
  a.budget_trials = 300;
  b.budget_trials = 40;
  const auto campaign = store->add_campaign("plans", Json::object(), 1, "", {a, b});
  const auto stages = store->stages(campaign);
  store->set_campaign_state(campaign, "running");
  store->transaction([&] {
    for (int i = 0; i < 340; ++i) {
      const bool first = i < 300;
      const auto t = store->add_trial(stages[first ? 0 : 1].id, first ? i : i - 300, {{"x", i}}, Json::object(),
                                      {{"step", i % 3 ? "explore" : "diversity"}}, static_cast<std::uint64_t>(i));
      store->start_attempt(t, 1, "local:worker-1", "host");
      if (i % 25 == 7) {
        store->set_trial_state(t, "failed", "boom");
        store->add_event(campaign, "trial_failed", {{"trial", i}});
        continue;
      }
      if (i == 0) {
        std::vector<store::MetricPoint> points;
        for (int k = 0; k < 500; ++k) points.push_back({"return", double(k), k == 9 ? std::nan("") : std::sin(k * 0.01), 1});
        for (int k = 0; k < 50; ++k) points.push_back({"loss", double(k), 1.0 / (k + 1), k < 25 ? 1 : 2});
        store->add_metrics(t, points);
      }
      store->complete_trial(t, {std::sin(i * 0.1)}, {"f0", "f1"}, {i * 0.01, 1 - i * 0.01}, Json::object(),
                            {{"trajectory", "t.jsonl", "00", 1}, {"result", "r.json", "00", 1}});
      store->set_trial_strategy(t, (i * 7) % 11);
    }
  });
  return db;
}

class QueryPlans : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new podium::testing::TempDir();
    db_ = new std::filesystem::path(build_campaign(dir_->path()));
  }
  static void TearDownTestSuite() {
    delete db_;
    delete dir_;
  }
  static podium::testing::TempDir* dir_;
  static std::filesystem::path* db_;

  // Every query the requests ran, with its plan; each fails the test if it grows with the trials.
  static std::vector<std::pair<std::string, std::vector<std::string>>> expect_no_scans(const std::vector<std::string>& paths) {
    auto plans = query_plans(*db_, statements_of(*db_, paths));
    for (const auto& [sql, plan] : plans)
      for (const auto& line : plan) EXPECT_FALSE(grows_with_trials(line)) << sql << joined(plan);
    return plans;
  }
};
podium::testing::TempDir* QueryPlans::dir_ = nullptr;
std::filesystem::path* QueryPlans::db_ = nullptr;

bool reads(const std::string& sql, const std::string& table) { return sql.find("FROM " + table + " ") != std::string::npos; }

// The five requests the campaign page makes at once (static/campaign.js; the latency bench's
// "campaign page"), and its other tables: strategies, trial pages by objective and by finishing
// time, a strategy filter, a trial, a scatter sampled from a larger stage.
TEST_F(QueryPlans, CampaignPageNeitherScansNorSorts) {
  const auto plans = expect_no_scans(
      {"/api/campaigns/1", "/api/campaigns/1/points", "/api/campaigns/1/trials?limit=1000&order=index&state=done",
       "/api/campaigns/1/events?last=50", "/api/campaigns/1/trials?offset=0&limit=50&order=index&desc=0",
       "/api/campaigns/1/strategies", "/api/campaigns/1/trials?limit=50&order=objective&offset=100",
       "/api/campaigns/1/trials?limit=50&order=finished&desc=1&offset=20",
       "/api/campaigns/1/trials?limit=50&order=finished&strategy=3", "/api/trials/5", "/api/campaigns/1/points?max_points=40"});
  // The trace saw what the page reads: trials, their features, artifacts, events, labels.
  std::set<std::string> tables;
  for (const auto& [sql, plan] : plans)
    for (const char* table : {"trials", "features", "artifacts", "events", "stage_strategy_counts"})
      if (reads(sql, table)) tables.insert(table);
  EXPECT_EQ(tables.size(), 5u) << "tables read: " << tables.size();
  // Strategy labels: one probe per strategy of trials_by_strategy_finish.
  bool labels = false;
  for (const auto& [sql, plan] : plans)
    if (reads(sql, "trials") && sql.find("ORDER BY finished_at, idx") != std::string::npos) {
      labels = true;
      EXPECT_NE(joined(plan).find("COVERING INDEX trials_by_strategy_finish"), std::string::npos) << sql << joined(plan);
    }
  EXPECT_TRUE(labels);
  // The scatter of a stage larger than max_points seeks its sampled trials by index.
  EXPECT_TRUE(std::any_of(plans.begin(), plans.end(), [](const auto& p) {
    return reads(p.first, "trials") && p.first.find("stage_id = ? AND idx = ?") != std::string::npos;
  }));
}

// The metric plot (the latency bench's 100,000-point series), with and without a name: one range
// of a covering index, so no metric row is read from the table.
TEST_F(QueryPlans, MetricSeriesIsReadFromACoveringIndex) {
  const auto plans = expect_no_scans({"/api/trials/1/metrics?max_points=100", "/api/trials/1/metrics?name=loss&max_points=10"});
  int series = 0;
  for (const auto& [sql, plan] : plans) {
    if (!reads(sql, "metrics")) continue;
    ++series;
    ASSERT_EQ(plan.size(), 1u) << sql << joined(plan);
    EXPECT_EQ(plan[0].rfind("SEARCH metrics USING COVERING INDEX metrics_by_series (trial_id=?", 0), 0u) << sql << joined(plan);
  }
  EXPECT_EQ(series, 2);
}

}  // namespace
}  // namespace podium::web_dashboard
