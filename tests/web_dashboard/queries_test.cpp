// The dashboard's read-only store queries: filters, ordering, scatter sampling, strategy
// summaries, metric downsampling, the change token, and no read transaction left open.
#include "podium/store/queries.h"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "process.h"

namespace podium::store {
namespace {

using podium::testing::TempDir;

struct Fixture {
  TempDir dir;
  std::filesystem::path db = dir / "q.db";
  std::int64_t campaign = 0;
  std::vector<std::int64_t> trials;

  // 30 trials over two stages: trial i has objective i, features (i, -i), strategy i % 3 in
  // stage 0, and is done except every 10th, which failed.
  Fixture() {
    auto s = Store::open(db, Store::Access::read_write);
    NewStage a{"a", "landscape", "random"}, b{"b", "landscape", "random"};
    a.budget_trials = b.budget_trials = 15;
    campaign = s->add_campaign("q", Json::object(), 1, "", {a, b});
    const auto stages = s->stages(campaign);
    for (int i = 0; i < 30; ++i) {
      const auto id =
          s->add_trial(stages[i / 15].id, i % 15, {{"x", i}}, Json::object(), {{"step", i % 2 ? "explore" : "diversity"}}, 1);
      trials.push_back(id);
      s->start_attempt(id, 1, "w", "h");
      if (i % 10 == 0) {
        s->set_trial_state(id, "failed", "boom");
        continue;
      }
      s->complete_trial(id, {double(i)}, {"f0", "f1"}, {double(i), -double(i)}, Json::object(), {});
      if (i < 15) s->set_trial_strategy(id, i % 3);
    }
  }
};

TEST(Queries, TrialPageFiltersByStageStateAndStrategy) {
  Fixture f;
  auto q = Queries::open(f.db);
  TrialFilter filter;
  EXPECT_EQ(q->trial_page(f.campaign, filter).total, 30);
  filter.stage_index = 1;
  EXPECT_EQ(q->trial_page(f.campaign, filter).total, 15);
  filter.state = "failed";
  const auto failed = q->trial_page(f.campaign, filter);  // failed: trials 0, 10, 20; stage 1 holds 20
  ASSERT_EQ(failed.total, 1);
  EXPECT_EQ(failed.trials[0].id, f.trials[20]);
  EXPECT_EQ(failed.trials[0].error, "boom");
  TrialFilter by_strategy;
  by_strategy.strategy = 2;  // done trials 2, 5, 8, 11, 14
  EXPECT_EQ(q->trial_page(f.campaign, by_strategy).total, 5);
}

TEST(Queries, TrialPageOrdersAndPages) {
  Fixture f;
  auto q = Queries::open(f.db);
  TrialFilter filter;
  filter.order = TrialFilter::Order::objective;
  filter.descending = true;
  filter.limit = 3;
  filter.offset = 1;
  const auto page = q->trial_page(f.campaign, filter);
  EXPECT_EQ(page.total, 30);
  ASSERT_EQ(page.trials.size(), 3u);
  EXPECT_EQ(Json::parse(page.trials[0].objectives)[0], 28.0);  // 29 is first; offset 1
  EXPECT_EQ(Json::parse(page.trials[2].objectives)[0], 26.0);
  EXPECT_EQ(page.trials[0].features, (std::vector<double>{28.0, -28.0}));
  filter.descending = false;
  filter.offset = 0;
  EXPECT_EQ(Json::parse(q->trial_page(f.campaign, filter).trials[0].objectives)[0], 1.0);  // no objective: last
}

// Every order, direction, filter and offset against a brute-force sort of all trials: pages
// merge the two stages' index walks into one order.
TEST(Queries, TrialPagesMatchABruteForceSortAcrossStages) {
  Fixture f;
  {
    auto s = Store::open(f.db, Store::Access::read_write);
    s->set_trial_strategy(f.trials[17], 2);  // a strategy in stage 1 too
  }
  auto q = Queries::open(f.db);
  const auto all = q->store().campaign_trials(f.campaign);
  std::map<std::int64_t, int> stage_of;
  for (const auto& st : q->store().stages(f.campaign)) stage_of[st.id] = st.index;
  using Order = TrialFilter::Order;
  for (const Order order : {Order::index, Order::objective, Order::finished})
    for (const bool descending : {false, true})
      for (const std::optional<std::string>& state : {std::optional<std::string>(), std::optional<std::string>("done")})
        for (const std::optional<std::int64_t> strategy : {std::optional<std::int64_t>(), std::optional<std::int64_t>(2)}) {
          std::vector<TrialRecord> expected;
          for (const auto& t : all)
            if ((!state || t.state == *state) && (!strategy || t.strategy == strategy)) expected.push_back(t);
          const auto key = [&](const TrialRecord& t) {
            const double sign = descending ? -1.0 : 1.0;
            if (order == Order::index) return std::make_tuple(0, sign * stage_of[t.stage_id], sign * double(t.index));
            if (order == Order::finished) return std::make_tuple(0, sign * t.finished_at, sign * double(t.id));
            if (t.objectives.is_null()) return std::make_tuple(1, 0.0, double(t.id));
            return std::make_tuple(0, sign * t.objectives[0].get<double>(), sign * double(t.id));
          };
          std::sort(expected.begin(), expected.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
          for (const std::int64_t offset : {0, 3, 12}) {
            TrialFilter filter;
            filter.order = order;
            filter.descending = descending;
            filter.state = state;
            filter.strategy = strategy;
            filter.offset = offset;
            filter.limit = 7;
            const auto page = q->trial_page(f.campaign, filter);
            EXPECT_EQ(page.total, static_cast<std::int64_t>(expected.size()));
            std::vector<std::int64_t> got, want;
            for (const auto& t : page.trials) got.push_back(t.id);
            for (std::size_t i = offset; i < expected.size() && i < std::size_t(offset + 7); ++i) want.push_back(expected[i].id);
            EXPECT_EQ(got, want) << "order " << int(order) << " desc " << descending << " state " << state.value_or("-")
                                 << " strategy " << strategy.value_or(-1) << " offset " << offset;
          }
        }
}

TEST(Queries, PointsAreDoneTrialsStridedWhenCapped) {
  Fixture f;
  auto q = Queries::open(f.db);
  std::int64_t total = 0;
  const auto all = q->points(f.campaign, 1000, &total);
  EXPECT_EQ(total, 27);
  ASSERT_EQ(all.size(), 27u);
  EXPECT_EQ(all[0].step, "explore");  // trial 1 (trial 0 failed)
  EXPECT_EQ(all[1].step, "diversity");
  EXPECT_EQ(all[0].features, (std::vector<double>{1.0, -1.0}));
  EXPECT_EQ(all[0].strategy, 1);
  EXPECT_FALSE(all.back().strategy.has_value());
  // Strided per stage: 13 done trials in stage 0 and 14 in stage 1, each at stride 2.
  const auto capped = q->points(f.campaign, 10, &total);
  EXPECT_EQ(total, 27);
  ASSERT_EQ(capped.size(), 14u);
  EXPECT_EQ(capped[1].id, all[2].id);
  EXPECT_EQ(capped[7].id, all[13].id);  // stage 1's first done trial
  EXPECT_EQ(capped[7].stage_index, 1);
  // A stage under the cap keeps every point beside one over it.
  const auto mixed = q->points(f.campaign, 13, &total);
  EXPECT_EQ(std::count_if(mixed.begin(), mixed.end(), [](const auto& p) { return p.stage_index == 0; }), 13);
  EXPECT_EQ(std::count_if(mixed.begin(), mixed.end(), [](const auto& p) { return p.stage_index == 1; }), 7);
}

// points() samples a large stage by index seeks where its indexes are dense and most trials are
// done, else by a walk of the done trials: both give exactly every stride-th done trial in index
// order, with its row and features, as a brute-force pass over the stage's trials does.
TEST(Queries, SampledPointsAreEveryStrideThDoneTrialWhateverTheStatesAndGaps) {
  TempDir dir;
  const auto db = dir / "p.db";
  std::int64_t campaign = 0;
  {
    auto s = Store::open(db, Store::Access::read_write);
    NewStage dense{"dense", "landscape", "random"}, gaps{"gaps", "landscape", "random"}, few{"few", "landscape", "random"};
    campaign = s->add_campaign("p", Json::object(), 1, "", {dense, gaps, few});
    const auto stages = s->stages(campaign);
    s->transaction([&] {
      for (int i = 0; i < 900; ++i) {
        const int stage = i / 300, k = i % 300;
        // Stage "gaps" has index gaps (only odd indexes); stage "few" has few done trials.
        const auto t = s->add_trial(stages[stage].id, stage == 1 ? 2 * k + 1 : k, {{"x", i}}, Json::object(),
                                    {{"step", k % 2 ? "explore" : "diversity"}}, 1);
        const int kind = stage == 2 ? (k % 5 == 0 ? 0 : 1 + k % 4) : (k % 7 == 3 ? 1 + k % 4 : 0);
        if (kind == 1) continue;  // pending
        s->start_attempt(t, 1, "w", "h");
        if (kind == 2) continue;  // running
        if (kind == 3 || kind == 4) {
          s->set_trial_state(t, kind == 3 ? "failed" : "cancelled", "x");
          continue;
        }
        s->complete_trial(t, {k * 0.5}, {"f0", "f1"}, {double(k), -double(k)}, Json::object(), {});
        if (k % 3) s->set_trial_strategy(t, k % 4);
      }
    });
  }
  auto q = Queries::open(db);
  const auto stages = q->store().stages(campaign);
  for (const std::int64_t max_points : {1, 7, 40, 99, 150, 299, 1000}) {
    std::vector<TrialPoint> expected;
    std::int64_t expected_total = 0;
    for (const auto& st : stages) {
      std::vector<TrialRecord> done;
      for (auto& t : q->store().trials(st.id))
        if (t.state == "done") done.push_back(std::move(t));
      const auto n = static_cast<std::int64_t>(done.size());
      expected_total += n;
      const std::int64_t stride = std::max<std::int64_t>(1, (n + max_points - 1) / max_points);
      for (std::int64_t i = 0; i < n; i += stride) {
        const auto& t = done[static_cast<std::size_t>(i)];
        TrialPoint p;
        p.id = t.id;
        p.stage_index = st.index;
        p.index = t.index;
        p.objective = t.objectives[0].get<double>();
        p.strategy = t.strategy;
        p.step = t.info.at("step").get<std::string>();
        p.finished_at = t.finished_at;
        p.features = t.features;
        expected.push_back(p);
      }
    }
    std::int64_t total = 0;
    const auto got = q->points(campaign, max_points, &total);
    EXPECT_EQ(total, expected_total);
    ASSERT_EQ(got.size(), expected.size()) << "max_points " << max_points;
    for (std::size_t k = 0; k < got.size(); ++k) {
      const auto& a = got[k];
      const auto& b = expected[k];
      EXPECT_EQ(std::tie(a.id, a.stage_index, a.index, a.objective, a.strategy, a.step, a.finished_at, a.features),
                std::tie(b.id, b.stage_index, b.index, b.objective, b.strategy, b.step, b.finished_at, b.features))
          << "max_points " << max_points << " point " << k;
    }
  }
}

TEST(Queries, TrialIdIsFoundByStageAndIndex) {
  Fixture f;
  auto q = Queries::open(f.db);
  const auto stages = q->store().stages(f.campaign);
  EXPECT_EQ(q->trial_id(stages[1].id, 5), f.trials[20]);
  EXPECT_EQ(q->trial_id(stages[0].id, 0), f.trials[0]);
  EXPECT_FALSE(q->trial_id(stages[0].id, 15).has_value());
}

TEST(Queries, StrategiesPickTheBestTrialAsRepresentative) {
  Fixture f;
  auto q = Queries::open(f.db);
  const auto s = q->strategies(f.campaign);
  ASSERT_EQ(s.size(), 3u);
  // In label order: the order found (trial 1 found strategy 1, trial 2 strategy 2, trial 3 strategy 0).
  EXPECT_EQ(s[0].strategy, 1);
  EXPECT_EQ(s[1].strategy, 2);
  EXPECT_EQ(s[2].strategy, 0);
  for (std::size_t k = 0; k < s.size(); ++k) EXPECT_EQ(s[k].label, static_cast<std::int64_t>(k) + 1);
  EXPECT_EQ(s[2].trials, 4);
  EXPECT_EQ(s[2].representative_trial, f.trials[12]);
  EXPECT_EQ(s[2].representative_index, 12);
  EXPECT_EQ(s[2].best_objective, 12.0);
  EXPECT_EQ(s[1].trials, 5);
  EXPECT_EQ(s[1].representative_features, (std::vector<double>{14.0, -14.0}));
  EXPECT_EQ(q->store().strategy_labels(q->store().stages(f.campaign)[0].id), (StrategyLabels{{1, 1}, {2, 2}, {0, 3}}));
  const auto summary = q->summary(f.campaign, now_unix_s());
  EXPECT_EQ(summary.strategy_table.size(), 3u);
  EXPECT_EQ(summary.best_objective, 29.0);
  EXPECT_EQ(summary.counts.failed, 3);
  EXPECT_EQ(summary.done_last_minute, 27);
}

// done_last_minute counts the shorter side of the minute's start: the same count as a recount
// wherever the minute starts (no trial in it, a few, half, all of a 3,000-trial stage), failed
// trials excluded, over two stages.
TEST(Queries, DoneLastMinuteEqualsARecountWhereverTheMinuteStarts) {
  TempDir dir;
  const auto db = dir / "m.db";
  std::int64_t campaign = 0;
  {
    auto s = Store::open(db, Store::Access::read_write);
    NewStage a{"a", "landscape", "random"}, b{"b", "landscape", "random"};
    campaign = s->add_campaign("m", Json::object(), 1, "", {a, b});
    const auto stages = s->stages(campaign);
    s->transaction([&] {
      for (int i = 0; i < 3100; ++i) {
        const auto t = s->add_trial(stages[i < 3000 ? 0 : 1].id, i, Json::object(), Json::object(), Json::object(), 1);
        s->start_attempt(t, 1, "w", "h");
        if (i % 97 == 5) s->set_trial_state(t, "failed", "boom");
        else s->complete_trial(t, {1.0}, {}, {}, Json::object(), {});
      }
    });
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);  // finishing times 1000 + index, exactly
    EXPECT_EQ(sqlite3_exec(raw, "UPDATE trials SET finished_at = 1000 + idx", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(raw);
  }
  auto q = Queries::open(db);
  const auto all = q->store().campaign_trials(campaign);
  for (const double start : {-5.0, 0.0, 1.0, 700.0, 1500.0, 2047.5, 2999.0, 3050.0, 3099.0, 4000.0}) {
    const auto recount = std::count_if(
        all.begin(), all.end(), [&](const TrialRecord& t) { return t.state == "done" && t.finished_at >= 1000.0 + start; });
    EXPECT_EQ(q->summary(campaign, 1060.0 + start).done_last_minute, recount) << "minute from " << start;
  }
}

TEST(Queries, MetricDownsamplingKeepsEveryBucketsMinAndMax) {
  Fixture f;
  {
    auto s = Store::open(f.db, Store::Access::read_write);
    std::vector<MetricPoint> points;
    for (int k = 0; k < 100000; ++k) points.push_back({"loss", double(k), std::sin(k * 1e-3)});
    points[54321].value = 50.0;  // a spike the plot must not lose
    points[777].value = std::nan("");
    s->transaction([&] { s->add_metrics(f.trials[1], points); });
    s->add_metrics(f.trials[1], {{"other", 0.0, 1.0}});
  }
  auto q = Queries::open(f.db);
  const auto series = q->metric_series(f.trials[1], 500, std::string("loss"));
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].total_points, 100000);
  EXPECT_LE(series[0].steps.size(), 1000u);
  EXPECT_GE(series[0].steps.size(), 500u);
  EXPECT_TRUE(std::is_sorted(series[0].steps.begin(), series[0].steps.end()));
  EXPECT_EQ(*std::max_element(series[0].values.begin(), series[0].values.end()), 50.0);
  EXPECT_NEAR(*std::min_element(series[0].values.begin(), series[0].values.end()), -1.0, 1e-6);
  EXPECT_EQ(q->metric_series(f.trials[1], 500, std::nullopt).size(), 2u);
  EXPECT_EQ(q->metric_series(f.trials[1], 500, std::string("loss' OR '1'='1")).size(), 0u);  // bound, not spliced
}

TEST(Queries, DataVersionChangesWhenAnotherConnectionCommits) {
  Fixture f;
  auto q = Queries::open(f.db);
  const auto v = q->data_version();
  EXPECT_EQ(q->data_version(), v);
  Store::open(f.db, Store::Access::read_write)->set_campaign_state(f.campaign, "paused");
  EXPECT_NE(q->data_version(), v);
}

// A reader that kept a read transaction open would pin the WAL: a TRUNCATE checkpoint could not
// finish. After every query the writer's checkpoint must complete.
TEST(Queries, NoReadTransactionOutlivesACall) {
  Fixture f;
  auto q = Queries::open(f.db);
  sqlite3* writer = nullptr;
  ASSERT_EQ(sqlite3_open_v2(f.db.c_str(), &writer, SQLITE_OPEN_READWRITE, nullptr), SQLITE_OK);
  const auto checkpoint_completes = [&] {
    int log = -1, done = -1;
    const int rc = sqlite3_wal_checkpoint_v2(writer, nullptr, SQLITE_CHECKPOINT_TRUNCATE, &log, &done);
    return rc == SQLITE_OK && log == 0;
  };
  // A first write makes the writer see WAL mode and leaves frames for the checkpoint to move.
  ASSERT_EQ(sqlite3_exec(writer, "UPDATE campaigns SET error = ''", nullptr, nullptr, nullptr), SQLITE_OK);
  std::int64_t total = 0;
  q->trial_page(f.campaign, {});
  q->points(f.campaign, 5, &total);
  q->strategies(f.campaign);
  q->summary(f.campaign, now_unix_s());
  q->metric_series(f.trials[1], 10, std::nullopt);
  q->trial(f.trials[3]);
  q->store().campaign_trials(f.campaign);
  EXPECT_TRUE(checkpoint_completes());
  // Control: an open read transaction on the same file does block it.
  sqlite3* reader = nullptr;
  ASSERT_EQ(sqlite3_open_v2(f.db.c_str(), &reader, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(reader, "BEGIN; SELECT count(*) FROM trials;", nullptr, nullptr, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(writer, "UPDATE campaigns SET error = 'x'", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_busy_timeout(writer, 0);
  EXPECT_FALSE(checkpoint_completes());
  sqlite3_exec(reader, "COMMIT", nullptr, nullptr, nullptr);
  sqlite3_close(reader);
  sqlite3_close(writer);
}

}  // namespace
}  // namespace podium::store

namespace podium::store {
namespace {

// Strategy ids are per stage: strategy 0 of stage 0 and strategy 0 of stage 1 are two strategies.
TEST(Queries, StrategiesAreCountedPerStage) {
  TempDir dir;
  auto s = Store::open(dir / "s.db", Store::Access::read_write);
  NewStage a{"a", "landscape", "random"}, b{"b", "landscape", "random"};
  a.budget_trials = b.budget_trials = 2;
  const auto campaign = s->add_campaign("s", Json::object(), 1, "", {a, b});
  const auto stages = s->stages(campaign);
  for (int stage = 0; stage < 2; ++stage) {
    const auto id = s->add_trial(stages[stage].id, 0, Json::object(), Json::object(), Json::object(), 1);
    s->complete_trial(id, {1.0}, {"f0"}, {0.5}, Json::object(), {});
    s->set_trial_strategy(id, 0);
  }
  auto q = Queries::open(dir / "s.db");
  const auto table = q->strategies(campaign);
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(table[0].stage_index, 0);
  EXPECT_EQ(table[1].stage_index, 1);
  EXPECT_EQ(q->summary(campaign, now_unix_s()).strategy_table.size(), 2u);
}

}  // namespace
}  // namespace podium::store
