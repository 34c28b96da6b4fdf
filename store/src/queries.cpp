#include "podium/store/queries.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <tuple>

#include "podium/base/error.h"
#include "records.h"
#include "sqlite.h"

namespace podium::store {

struct Queries::Impl {
  sqlite3* db = nullptr;
  ~Impl() {
    if (db) sqlite3_close_v2(db);
  }
};

namespace {

// One read transaction for the statements of one call: a consistent snapshot, and SQLite takes
// the WAL read lock once instead of once per statement (a 5,000-point scatter runs 10,000
// statements). Ends (COMMIT) before the call returns; nested calls join the outer one. Declare it
// before the call's statements, so they are finalised first.
class ReadSnapshot {
 public:
  explicit ReadSnapshot(sqlite3* db) : db_(sqlite3_get_autocommit(db) ? db : nullptr) {
    if (db_) check_sqlite(db_, sqlite3_exec(db_, "BEGIN", nullptr, nullptr, nullptr), "BEGIN");
  }
  ~ReadSnapshot() {
    if (db_) sqlite3_exec(db_, "COMMIT", nullptr, nullptr, nullptr);
  }
  ReadSnapshot(const ReadSnapshot&) = delete;
  ReadSnapshot& operator=(const ReadSnapshot&) = delete;

 private:
  sqlite3* db_;
};

struct StageRef {
  std::int64_t id = 0, index = 0;
};

// The campaign's stages in index order (only stage_index if given).
std::vector<StageRef> campaign_stages(sqlite3* db, std::int64_t campaign_id, std::optional<int> stage_index) {
  Statement s(db, "SELECT id, idx FROM stages WHERE campaign_id = ?1 AND (?2 IS NULL OR idx = ?2) ORDER BY idx");
  s.bind(1, campaign_id);
  stage_index ? s.bind(2, static_cast<std::int64_t>(*stage_index)) : s.bind_null(2);
  std::vector<StageRef> out;
  while (s.step()) out.push_back({s.int64(0), s.int64(1)});
  return out;
}

// Per-stage statements are fixed SQL fragments joined by which filters are set (so SQLite can
// pick the index that serves them); the values are always bound: ?1 stage, ?2 state, ?3 strategy.
std::string stage_where(const TrialFilter& f) {
  std::string where = "WHERE stage_id = ?1";
  if (f.state) where += " AND state = ?2";
  if (f.strategy) where += " AND strategy = ?3";
  return where;
}

void bind_stage_filter(Statement& s, std::int64_t stage_id, const TrialFilter& f) {
  s.reset();
  s.bind(1, stage_id);
  if (f.state) s.bind(2, *f.state);
  if (f.strategy) s.bind(3, *f.strategy);
}

// Trials matching the filter: from the v3 counts unless both state and strategy are filtered.
std::int64_t count_matching(sqlite3* db, const std::vector<StageRef>& stages, const TrialFilter& f) {
  const std::string sql = !f.strategy ? (f.state ? "SELECT trials FROM stage_state_counts WHERE stage_id = ?1 AND state = ?2"
                                                 : "SELECT sum(trials) FROM stage_state_counts WHERE stage_id = ?1")
                          : !f.state  ? "SELECT trials FROM stage_strategy_counts WHERE stage_id = ?1 AND strategy = ?3"
                                      : "SELECT count(*) FROM trials " + stage_where(f);
  Statement s(db, sql.c_str());
  std::int64_t total = 0;
  for (const auto& st : stages) {
    bind_stage_filter(s, st.id, f);
    if (s.step() && !s.is_null(0)) total += s.int64(0);
  }
  return total;
}

// A trial's place in the page order (group, key, tie; unique within a campaign) and its id.
struct Ranked {
  std::int64_t group = 0;
  double key = 0;
  std::int64_t tie = 0, id = 0;
  bool operator<(const Ranked& o) const { return std::tie(group, key, tie) < std::tie(o.group, o.key, o.tie); }
};

// One walk of one stage: its first `cap` matching trials in page order, read from an index of
// the stage in that order, so the campaign's trials are never sorted; a multi-stage page merges
// the stages' walks. order=finished without a state filter walks trials_by_finish once per state
// the stage has trials in (each_state: ?2 bound to it) and merges those too. Not covered by an
// index: a state filter with order=objective or a strategy filter with order=index or finished
// (checked on each row the walk passes).
struct Walk {
  std::string sql;
  std::function<Ranked(const Statement&, std::int64_t stage_position)> rank;
  bool each_state = false;
};

std::vector<Walk> walks(const TrialFilter& f) {
  const double sign = f.descending ? -1.0 : 1.0;
  const auto isign = static_cast<std::int64_t>(sign);
  const std::string where = stage_where(f), dir = f.descending ? " DESC" : "";
  switch (f.order) {
    case TrialFilter::Order::objective:  // trials without an objective last, by id
      return {{"SELECT id, objective FROM trials " + where + " AND objective IS NOT NULL ORDER BY objective" + dir + ", id" +
                   dir + " LIMIT ?4",
               [=](const Statement& s, std::int64_t) {
                 return Ranked{0, sign * s.real(1), isign * s.int64(0), s.int64(0)};
               }},
              {"SELECT id FROM trials " + where + " AND objective IS NULL ORDER BY id LIMIT ?4",
               [](const Statement& s, std::int64_t) {
                 return Ranked{1, 0, s.int64(0), s.int64(0)};
               }}};
    case TrialFilter::Order::finished:
      return {{"SELECT id, finished_at FROM trials " + where + (f.state ? "" : " AND state = ?2") + " ORDER BY finished_at" +
                   dir + ", id" + dir + " LIMIT ?4",
               [=](const Statement& s, std::int64_t) {
                 return Ranked{0, sign * s.real(1), isign * s.int64(0), s.int64(0)};
               },
               !f.state}};
    case TrialFilter::Order::index:
      break;
  }
  return {{"SELECT id, idx FROM trials " + where + " ORDER BY idx" + dir + " LIMIT ?4",
           [=](const Statement& s, std::int64_t position) {
             return Ranked{isign * position, 0, isign * s.int64(1), s.int64(0)};
           }}};
}

std::optional<double> optional_real(const Statement& s, int column) {
  if (s.is_null(column)) return std::nullopt;
  return s.real(column);
}

}  // namespace

Queries::Queries(std::unique_ptr<Store> store, std::unique_ptr<Impl> impl) : store_(std::move(store)), impl_(std::move(impl)) {}
Queries::~Queries() = default;

std::unique_ptr<Queries> Queries::open(const std::filesystem::path& path) {
  auto store = Store::open(path, Store::Access::read_only);  // existence and schema checks
  auto impl = std::make_unique<Impl>();
  impl->db = open_for_reading(path);  // also on a read-only filesystem
  sqlite3_busy_timeout(impl->db, 10000);
  // Scans of 100,000-trial campaigns: memory-mapped reads and a page cache that holds the trials.
  check_sqlite(impl->db,
               sqlite3_exec(impl->db, "PRAGMA mmap_size = 268435456; PRAGMA cache_size = -32768", nullptr, nullptr, nullptr),
               "PRAGMA");
  return std::unique_ptr<Queries>(new Queries(std::move(store), std::move(impl)));
}

std::int64_t Queries::data_version() const {
  Statement s(impl_->db, "PRAGMA data_version");
  s.step();
  return s.int64(0);
}

std::optional<TrialRecord> Queries::trial(std::int64_t trial_id) const {
  const ReadSnapshot snapshot(impl_->db);
  Statement s(impl_->db, (std::string(kTrialSelect) + "WHERE t.id = ?").c_str());
  Statement features(impl_->db, kTrialFeatures);
  s.bind(1, trial_id);
  if (!s.step()) return std::nullopt;
  auto t = read_trial(s);
  t.features = read_features(features, trial_id);
  return t;
}

std::optional<std::int64_t> Queries::trial_campaign(std::int64_t trial_id) const {
  Statement s(impl_->db, "SELECT st.campaign_id FROM trials t JOIN stages st ON st.id = t.stage_id WHERE t.id = ?");
  s.bind(1, trial_id);
  if (!s.step()) return std::nullopt;
  return s.int64(0);
}

std::optional<std::int64_t> Queries::trial_id(std::int64_t stage_id, std::int64_t index) const {
  Statement s(impl_->db, "SELECT id FROM trials WHERE stage_id = ? AND idx = ?");
  s.bind(1, stage_id).bind(2, index);
  if (!s.step()) return std::nullopt;
  return s.int64(0);
}

namespace {

// The indexes (trials.idx) of a stage's done trials of rank 0, stride, 2 stride, ... in index
// order, found without walking the done trials: when the stage's indexes are dense (min..max, a
// trial each) and most of its trials are done, the done trial of rank k has index min + k plus the
// number of other trials at or below it, and those others are walked instead (trials_by_state, per
// state). nullopt where a walk of the done trials costs no more, or the indexes have gaps.
std::optional<std::vector<std::int64_t>> sampled_done_indexes(sqlite3* db, std::int64_t stage_id, std::int64_t done,
                                                              std::int64_t stride) {
  Statement states(db, "SELECT state, trials FROM stage_state_counts WHERE stage_id = ? AND trials > 0");
  states.bind(1, stage_id);
  std::int64_t trials = 0;
  std::vector<std::string> other_states;
  while (states.step()) {
    trials += states.int64(1);
    if (states.text(0) != "done") other_states.push_back(states.text(0));
  }
  if (stride == 1 || 2 * (trials - done) > done) return std::nullopt;
  Statement range(db,
                  "SELECT (SELECT min(idx) FROM trials WHERE stage_id = ?1), (SELECT max(idx) FROM trials WHERE stage_id = ?1)");
  range.bind(1, stage_id);
  if (!range.step() || range.is_null(0) || range.int64(0) < 0 || range.int64(1) - range.int64(0) + 1 != trials)
    return std::nullopt;
  const std::int64_t first = range.int64(0);
  std::vector<std::int64_t> others;  // the indexes of the stage's trials that are not done
  Statement walk(db, "SELECT idx FROM trials WHERE stage_id = ? AND state = ? ORDER BY idx");
  for (const auto& state : other_states) {
    walk.reset();
    walk.bind(1, stage_id).bind(2, state);
    while (walk.step()) others.push_back(walk.int64(0));
  }
  std::sort(others.begin(), others.end());
  std::vector<std::int64_t> out;
  std::size_t below = 0;  // others at or below the candidate index
  for (std::int64_t rank = 0; rank < done; rank += stride) {
    while (below < others.size() && others[below] <= first + rank + static_cast<std::int64_t>(below)) ++below;
    out.push_back(first + rank + static_cast<std::int64_t>(below));
  }
  return out;
}

constexpr const char* kPointColumns =
    "SELECT id, idx, objective, strategy, json_extract(info, '$.step'), finished_at, state FROM trials ";

// The current row of a kPointColumns statement, or nullopt unless the trial is done.
std::optional<TrialPoint> read_point(const Statement& row, std::int64_t stage_index) {
  if (row.text(6) != "done") return std::nullopt;
  TrialPoint p;
  p.id = row.int64(0);
  p.stage_index = stage_index;
  p.index = row.int64(1);
  p.objective = optional_real(row, 2).value_or(std::nan(""));
  if (!row.is_null(3)) p.strategy = row.int64(3);
  p.step = row.text(4);
  p.finished_at = row.real(5);
  return p;
}

}  // namespace

std::vector<TrialPoint> Queries::points(std::int64_t campaign_id, std::int64_t max_points, std::int64_t* total) const {
  const ReadSnapshot snapshot(impl_->db);
  const auto stages = campaign_stages(impl_->db, campaign_id, std::nullopt);
  TrialFilter done;
  done.state = "done";
  if (total) *total = 0;
  // Every stride-th done trial in index order, strided per stage (the dashboard shows one stage at
  // a time, and a small stage keeps its points beside a large one): found by index seeks where
  // sampled_done_indexes can, else by a walk of the done trials' ids (trials_by_state, no row
  // read); only the sampled trials' rows and features are read.
  Statement done_ids(impl_->db, "SELECT id FROM trials WHERE stage_id = ? AND state = 'done' ORDER BY idx");
  Statement by_id(impl_->db, (std::string(kPointColumns) + "WHERE id = ?").c_str());
  Statement by_index(impl_->db, (std::string(kPointColumns) + "WHERE stage_id = ? AND idx = ?").c_str());
  Statement features(impl_->db, kTrialFeatures);
  std::vector<TrialPoint> out;
  for (const auto& st : stages) {
    const std::int64_t n = count_matching(impl_->db, {st}, done);
    if (total) *total += n;
    const std::int64_t stride = std::max<std::int64_t>(1, (n + max_points - 1) / std::max<std::int64_t>(1, max_points));
    const std::size_t first = out.size();
    const auto sample = sampled_done_indexes(impl_->db, st.id, n, stride);
    bool sampled = sample.has_value();
    for (std::size_t k = 0; sampled && k < sample->size(); ++k) {
      by_index.reset();
      by_index.bind(1, st.id).bind(2, (*sample)[k]);
      auto p = by_index.step() ? read_point(by_index, st.index) : std::nullopt;
      sampled = p.has_value();  // else the counts disagree with the rows: walk instead
      if (p) out.push_back(std::move(*p));
    }
    if (!sampled) {
      out.resize(first);
      done_ids.reset();
      done_ids.bind(1, st.id);
      for (std::int64_t i = 0; done_ids.step(); ++i) {
        if (i % stride != 0) continue;
        by_id.reset();
        by_id.bind(1, done_ids.int64(0));
        if (auto p = by_id.step() ? read_point(by_id, st.index) : std::nullopt) out.push_back(std::move(*p));
      }
    }
    for (std::size_t k = first; k < out.size(); ++k) out[k].features = read_features(features, out[k].id);
  }
  return out;
}

namespace {

// How many of a stage's `done` trials finished at or after `since`: counted on whichever side of
// `since` in trials_by_finish is shorter (the other side is `done` minus it), in rounds of growing
// length on both sides, so the cost follows the shorter side (a little over twice its length at
// most) rather than the recent side: a stage that finished 100,000 trials within the minute counts
// none of them.
std::int64_t done_since(sqlite3* db, std::int64_t stage_id, std::int64_t done, double since) {
  Statement s(db,
              "SELECT (SELECT count(*) FROM (SELECT 1 FROM trials WHERE stage_id = ?1 AND state = 'done' AND finished_at >= ?2 "
              "LIMIT ?3)), (SELECT count(*) FROM (SELECT 1 FROM trials WHERE stage_id = ?1 AND state = 'done' AND "
              "finished_at < ?2 LIMIT ?3))");
  for (std::int64_t cap = 1024;; cap *= 4) {
    s.reset();
    s.bind(1, stage_id).bind(2, since).bind(3, cap);
    if (!s.step()) return 0;
    if (s.int64(0) < cap) return s.int64(0);
    if (s.int64(1) < cap) return std::max<std::int64_t>(0, done - s.int64(1));
  }
}

}  // namespace

CampaignSummary Queries::summary(std::int64_t campaign_id, double now_unix_s) const {
  const ReadSnapshot snapshot(impl_->db);
  // Counts from the v3 count rows; the rest are min/max probes of an index per stage, so the cost
  // does not grow with the number of trials, and done_last_minute, a count of the shorter side of
  // the minute's start in trials_by_finish (done_since).
  CampaignSummary out;
  Statement counts(impl_->db,
                   "SELECT c.stage_id, c.state, c.trials FROM stages st JOIN stage_state_counts c ON c.stage_id = st.id "
                   "WHERE st.campaign_id = ? AND c.trials > 0");
  counts.bind(1, campaign_id);
  while (counts.step()) {
    const std::string state = counts.text(1);
    add_to_counts(out.counts, state, counts.int64(2));
    add_to_counts(out.stage_counts[counts.int64(0)], state, counts.int64(2));
  }
  Statement probe(impl_->db,
                  "SELECT (SELECT max(objective) FROM trials WHERE stage_id = ?1), "
                  "(SELECT min(finished_at) FROM trials WHERE stage_id = ?1 AND state = 'done'), "
                  "(SELECT max(finished_at) FROM trials WHERE stage_id = ?1 AND state = 'done')");
  for (const auto& st : campaign_stages(impl_->db, campaign_id, std::nullopt)) {
    probe.reset();
    probe.bind(1, st.id);
    probe.step();
    if (const auto best = optional_real(probe, 0)) out.best_objective = std::max(*best, out.best_objective.value_or(*best));
    if (!probe.is_null(1)) {
      out.first_finished_at = out.first_finished_at > 0 ? std::min(out.first_finished_at, probe.real(1)) : probe.real(1);
      out.last_finished_at = std::max(out.last_finished_at, probe.real(2));
    }
    const auto stage = out.stage_counts.find(st.id);
    if (stage != out.stage_counts.end() && stage->second.done > 0)
      out.done_last_minute += done_since(impl_->db, st.id, stage->second.done, now_unix_s - 60.0);
  }
  out.strategy_table = strategies(campaign_id);
  return out;
}

std::vector<StrategySummary> Queries::strategies(std::int64_t campaign_id) const {
  const ReadSnapshot snapshot(impl_->db);
  // The strategies and their sizes from the v3 count rows; per strategy, its best trial (the
  // earliest of equals) from trials_by_strategy (stage, strategy, objective).
  Statement list(impl_->db,
                 "SELECT st.id, st.idx, c.strategy, c.trials FROM stages st "
                 "JOIN stage_strategy_counts c ON c.stage_id = st.id WHERE st.campaign_id = ? AND c.trials > 0 "
                 "ORDER BY st.idx, c.strategy");
  list.bind(1, campaign_id);
  Statement best(impl_->db,
                 "SELECT id, idx, objective FROM trials WHERE stage_id = ?1 AND strategy = ?2 AND objective IS "
                 "(SELECT max(objective) FROM trials WHERE stage_id = ?1 AND strategy = ?2) ORDER BY id LIMIT 1");
  Statement features(impl_->db, kTrialFeatures);
  std::vector<StrategySummary> out;
  std::map<std::int64_t, StrategyLabels> labels;  // by stage id
  while (list.step()) {
    StrategySummary r;
    r.stage_index = list.int64(1);
    r.strategy = list.int64(2);
    r.trials = list.int64(3);
    auto stage_labels = labels.find(list.int64(0));
    if (stage_labels == labels.end()) stage_labels = labels.emplace(list.int64(0), store_->strategy_labels(list.int64(0))).first;
    const auto label = stage_labels->second.find(r.strategy);
    r.label = label != stage_labels->second.end() ? label->second : 0;
    best.reset();
    best.bind(1, list.int64(0)).bind(2, r.strategy);
    if (best.step()) {
      r.representative_trial = best.int64(0);
      r.representative_index = best.int64(1);
      r.best_objective = optional_real(best, 2).value_or(std::nan(""));
      r.representative_features = read_features(features, r.representative_trial);
    }
    out.push_back(std::move(r));
  }
  std::stable_sort(out.begin(), out.end(), [](const StrategySummary& a, const StrategySummary& b) {
    return a.stage_index != b.stage_index ? a.stage_index < b.stage_index : a.label < b.label;
  });
  return out;
}

TrialPage Queries::trial_page(std::int64_t campaign_id, const TrialFilter& filter) const {
  const ReadSnapshot snapshot(impl_->db);
  TrialPage page;
  const auto stages = campaign_stages(impl_->db, campaign_id, filter.stage_index);
  page.total = count_matching(impl_->db, stages, filter);
  const std::int64_t offset = std::max<std::int64_t>(0, filter.offset), limit = std::max<std::int64_t>(0, filter.limit);
  const std::int64_t cap = offset > INT64_MAX - limit ? INT64_MAX : offset + limit;
  if (limit == 0 || offset >= page.total) return page;
  // Each walk yields at most `cap` ids; the page is the [offset, cap) slice of their merge.
  std::vector<Ranked> ranked;
  Statement states(impl_->db, "SELECT state FROM stage_state_counts WHERE stage_id = ? AND trials > 0");
  for (const auto& walk : walks(filter)) {
    Statement s(impl_->db, walk.sql.c_str());
    for (std::size_t position = 0; position < stages.size(); ++position) {
      std::vector<std::optional<std::string>> each{std::nullopt};
      if (walk.each_state) {
        each.clear();
        states.reset();
        states.bind(1, stages[position].id);
        while (states.step()) each.emplace_back(states.text(0));
      }
      for (const auto& state : each) {
        bind_stage_filter(s, stages[position].id, filter);
        if (state) s.bind(2, *state);
        s.bind(4, cap);
        while (s.step()) ranked.push_back(walk.rank(s, static_cast<std::int64_t>(position)));
      }
    }
  }
  const auto end = ranked.begin() + std::min<std::int64_t>(cap, static_cast<std::int64_t>(ranked.size()));
  std::partial_sort(ranked.begin(), end, ranked.end());
  Statement row(impl_->db, (std::string(kTrialSelect) + "WHERE t.id = ?").c_str());
  Statement features(impl_->db, kTrialFeatures);
  for (auto it = ranked.begin() + std::min<std::int64_t>(offset, end - ranked.begin()); it != end; ++it) {
    row.reset();
    row.bind(1, it->id);
    if (!row.step()) continue;
    page.trials.push_back(read_trial_text(row));
    page.trials.back().features = read_features(features, it->id);
  }
  return page;
}

std::vector<Json> Queries::last_events(std::int64_t campaign_id, std::int64_t last_n) const {
  // Newest first from events_by_campaign, so only the rows returned are read and parsed.
  Statement s(impl_->db, "SELECT time, kind, payload FROM events WHERE campaign_id = ? ORDER BY id DESC LIMIT ?");
  s.bind(1, campaign_id).bind(2, last_n);
  std::vector<Json> out;
  while (s.step()) out.push_back({{"time", s.real(0)}, {"kind", s.text(1)}, {"payload", parse_json(s.text(2))}});
  std::reverse(out.begin(), out.end());
  return out;
}

namespace {
// Keeps the min and the max of each of max_points buckets, in step order.
void downsample(MetricSeries& m, std::int64_t max_points) {
  const auto n = static_cast<std::int64_t>(m.steps.size());
  if (n <= 2 * max_points) return;
  std::vector<double> steps, values;
  for (std::int64_t b = 0; b < max_points; ++b) {
    const std::int64_t lo = b * n / max_points, hi = (b + 1) * n / max_points;
    std::int64_t imin = lo, imax = lo;
    for (std::int64_t i = lo; i < hi; ++i) {
      if (std::isnan(m.values[i])) continue;
      if (std::isnan(m.values[imin]) || m.values[i] < m.values[imin]) imin = i;
      if (std::isnan(m.values[imax]) || m.values[i] > m.values[imax]) imax = i;
    }
    for (std::int64_t i : {std::min(imin, imax), std::max(imin, imax)}) {
      steps.push_back(m.steps[i]);
      values.push_back(m.values[i]);
      if (imin == imax) break;
    }
  }
  m.steps = std::move(steps);
  m.values = std::move(values);
}
}  // namespace

std::vector<MetricSeries> Queries::metric_series(std::int64_t trial_id, std::int64_t max_points,
                                                 const std::optional<std::string>& name) const {
  // One range of metrics_by_series (trial_id, name, step, attempt, value), in its order, so SQLite
  // neither sorts nor reads the table; attempts are split here. A name is a separate statement,
  // so it narrows the range rather than being checked on every point of the trial.
  Statement s(impl_->db, name ? "SELECT name, attempt, step, value FROM metrics WHERE trial_id = ?1 AND name = ?2 ORDER BY step"
                              : "SELECT name, attempt, step, value FROM metrics WHERE trial_id = ?1 ORDER BY name, step");
  s.bind(1, trial_id);
  if (name) s.bind(2, *name);
  std::vector<MetricSeries> out;
  std::map<int, MetricSeries> attempts;  // of the current name
  const auto flush = [&] {
    for (auto& [attempt, m] : attempts) out.push_back(std::move(m));
    attempts.clear();
  };
  std::string current;
  while (s.step()) {
    const std::string metric = s.text(0);
    if (metric != current) {
      flush();
      current = metric;
    }
    const int attempt = static_cast<int>(s.int64(1));
    auto& m = attempts[attempt];
    if (m.steps.empty()) {
      m.name = metric;
      m.attempt = attempt;
    }
    m.steps.push_back(s.real(2));
    m.values.push_back(s.is_null(3) ? std::nan("") : s.real(3));
  }
  flush();
  for (auto& m : out) {
    m.total_points = static_cast<std::int64_t>(m.steps.size());
    downsample(m, std::max<std::int64_t>(1, max_points));
  }
  return out;
}

}  // namespace podium::store
