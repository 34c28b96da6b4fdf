#include "podium/store/queries.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

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

// Filters are fixed SQL with bound values: a NULL parameter disables its condition.
constexpr const char* kTrialWhere =
    "WHERE st.campaign_id = ?1 AND (?2 IS NULL OR st.idx = ?2) AND (?3 IS NULL OR t.state = ?3) "
    "AND (?4 IS NULL OR t.strategy = ?4) ";

void bind_filter(Statement& s, std::int64_t campaign_id, const TrialFilter& f) {
  s.bind(1, campaign_id);
  f.stage_index ? s.bind(2, static_cast<std::int64_t>(*f.stage_index)) : s.bind_null(2);
  s.bind(3, f.state);
  f.strategy ? s.bind(4, *f.strategy) : s.bind_null(4);
}

// The ORDER BY clause is picked from constants, never built from request text.
const char* order_clause(TrialFilter::Order order, bool descending) {
  switch (order) {
    case TrialFilter::Order::objective:
      return descending ? "ORDER BY t.objective IS NULL, t.objective DESC, t.id "
                        : "ORDER BY t.objective IS NULL, t.objective, t.id ";
    case TrialFilter::Order::finished:
      return descending ? "ORDER BY t.finished_at DESC, t.id DESC " : "ORDER BY t.finished_at, t.id ";
    case TrialFilter::Order::index:
      break;
  }
  return descending ? "ORDER BY st.idx DESC, t.idx DESC " : "ORDER BY st.idx, t.idx ";
}

}  // namespace

Queries::Queries(std::unique_ptr<Store> store, std::unique_ptr<Impl> impl)
    : store_(std::move(store)), impl_(std::move(impl)) {}
Queries::~Queries() = default;

std::unique_ptr<Queries> Queries::open(const std::filesystem::path& path) {
  auto store = Store::open(path, Store::Access::read_only);  // existence and schema checks
  auto impl = std::make_unique<Impl>();
  const int rc = sqlite3_open_v2(path.c_str(), &impl->db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK)
    throw base::RuntimeError(path.string() + ": cannot open database: " +
                             (impl->db ? sqlite3_errmsg(impl->db) : sqlite3_errstr(rc)));
  sqlite3_busy_timeout(impl->db, 10000);
  // Scans of 100,000-trial campaigns: memory-mapped reads and a page cache that holds the trials.
  check_sqlite(impl->db, sqlite3_exec(impl->db, "PRAGMA mmap_size = 268435456; PRAGMA cache_size = -32768", nullptr, nullptr, nullptr),
               "PRAGMA");
  return std::unique_ptr<Queries>(new Queries(std::move(store), std::move(impl)));
}

std::int64_t Queries::data_version() const {
  Statement s(impl_->db, "PRAGMA data_version");
  s.step();
  return s.int64(0);
}

std::optional<TrialRecord> Queries::trial(std::int64_t trial_id) const {
  Statement s(impl_->db, (std::string(kTrialSelect) + "WHERE t.id = ?").c_str());
  s.bind(1, trial_id);
  if (!s.step()) return std::nullopt;
  return read_trial(s);
}

std::optional<std::int64_t> Queries::trial_campaign(std::int64_t trial_id) const {
  Statement s(impl_->db, "SELECT st.campaign_id FROM trials t JOIN stages st ON st.id = t.stage_id WHERE t.id = ?");
  s.bind(1, trial_id);
  if (!s.step()) return std::nullopt;
  return s.int64(0);
}

namespace {
// The primary objective column (schema v2), NULL until a trial is done.
std::optional<double> optional_real(const Statement& s, int column) {
  if (s.is_null(column)) return std::nullopt;
  return s.real(column);
}

void count_state(TrialCounts& c, const std::string& state, std::int64_t n) {
  c.total += n;
  if (state == "pending") c.pending += n;
  else if (state == "running") c.running += n;
  else if (state == "done") c.done += n;
  else if (state == "failed") c.failed += n;
  else if (state == "interrupted") c.interrupted += n;
  else if (state == "cancelled") c.cancelled += n;
}

}  // namespace

std::vector<TrialPoint> Queries::points(std::int64_t campaign_id, std::int64_t max_points, std::int64_t* total) const {
  // The ids of done trials (an index scan), then full rows for every stride-th one only.
  Statement ids(impl_->db,
                "SELECT t.id FROM trials t JOIN stages st ON st.id = t.stage_id "
                "WHERE st.campaign_id = ? AND t.state = 'done'");
  ids.bind(1, campaign_id);
  std::vector<std::int64_t> done;
  while (ids.step()) done.push_back(ids.int64(0));
  if (total) *total = static_cast<std::int64_t>(done.size());
  const auto n = static_cast<std::int64_t>(done.size());
  const std::int64_t stride = std::max<std::int64_t>(1, (n + max_points - 1) / std::max<std::int64_t>(1, max_points));
  Statement row(impl_->db,
                "SELECT st.idx, t.idx, t.objective, t.strategy, json_extract(t.info, '$.step'), t.finished_at "
                "FROM trials t JOIN stages st ON st.id = t.stage_id WHERE t.id = ?");
  Statement features(impl_->db, "SELECT value FROM features WHERE trial_id = ? ORDER BY idx");
  std::vector<TrialPoint> out;
  for (std::int64_t i = 0; i < n; i += stride) {
    row.reset();
    row.bind(1, done[i]);
    if (!row.step()) continue;
    TrialPoint p;
    p.id = done[i];
    p.stage_index = row.int64(0);
    p.index = row.int64(1);
    p.objective = optional_real(row, 2).value_or(std::nan(""));
    if (!row.is_null(3)) p.strategy = row.int64(3);
    p.step = row.text(4);
    p.finished_at = row.real(5);
    features.reset();
    features.bind(1, p.id);
    while (features.step()) p.features.push_back(features.real(0));
    out.push_back(std::move(p));
  }
  return out;
}

CampaignSummary Queries::summary(std::int64_t campaign_id, double now_unix_s) const {
  // Aggregates only, each answered from one of the v2 covering indexes (no row is read).
  CampaignSummary out;
  Statement counts(impl_->db,
                   "SELECT t.stage_id, t.state, count(*) FROM stages st JOIN trials t ON t.stage_id = st.id "
                   "WHERE st.campaign_id = ? GROUP BY t.stage_id, t.state");
  counts.bind(1, campaign_id);
  while (counts.step()) {
    const std::string state = counts.text(1);
    count_state(out.counts, state, counts.int64(2));
    count_state(out.stage_counts[counts.int64(0)], state, counts.int64(2));
  }
  Statement finish(impl_->db,
                   "SELECT min(t.finished_at), max(t.finished_at), sum(t.finished_at >= ?) FROM stages st "
                   "JOIN trials t ON t.stage_id = st.id WHERE st.campaign_id = ? AND t.state = 'done'");
  finish.bind(1, now_unix_s - 60.0).bind(2, campaign_id);
  if (finish.step() && !finish.is_null(0)) {
    out.first_finished_at = finish.real(0);
    out.last_finished_at = finish.real(1);
    out.done_last_minute = finish.int64(2);
  }
  Statement best(impl_->db,
                 "SELECT max(t.objective) FROM stages st JOIN trials t ON t.stage_id = st.id WHERE st.campaign_id = ?");
  best.bind(1, campaign_id);
  if (best.step()) out.best_objective = optional_real(best, 0);
  // Per strategy: SQLite returns the bare column t.id from the row holding max(objective).
  Statement strategies(impl_->db,
                       "SELECT st.idx, t.strategy, count(*), max(t.objective), t.id FROM stages st "
                       "JOIN trials t ON t.stage_id = st.id WHERE st.campaign_id = ? AND t.strategy IS NOT NULL "
                       "GROUP BY st.idx, t.strategy ORDER BY st.idx, t.strategy");
  strategies.bind(1, campaign_id);
  Statement features(impl_->db, "SELECT value FROM features WHERE trial_id = ? ORDER BY idx");
  while (strategies.step()) {
    StrategySummary r;
    r.stage_index = strategies.int64(0);
    r.strategy = strategies.int64(1);
    r.trials = strategies.int64(2);
    r.best_objective = optional_real(strategies, 3).value_or(std::nan(""));
    r.representative_trial = strategies.int64(4);
    features.reset();
    features.bind(1, r.representative_trial);
    while (features.step()) r.representative_features.push_back(features.real(0));
    out.strategy_table.push_back(std::move(r));
  }
  out.strategies = static_cast<std::int64_t>(out.strategy_table.size());
  return out;
}

TrialPage Queries::trial_page(std::int64_t campaign_id, const TrialFilter& filter) const {
  TrialPage page;
  Statement count(impl_->db,
                  (std::string("SELECT count(*) FROM trials t JOIN stages st ON st.id = t.stage_id ") + kTrialWhere).c_str());
  bind_filter(count, campaign_id, filter);
  count.step();
  page.total = count.int64(0);
  // Order and cut ids first, then read the full rows of the page only (features, JSON text).
  Statement ids(impl_->db, (std::string("SELECT t.id FROM trials t JOIN stages st ON st.id = t.stage_id ") + kTrialWhere +
                            order_clause(filter.order, filter.descending) + "LIMIT ?5 OFFSET ?6")
                               .c_str());
  bind_filter(ids, campaign_id, filter);
  ids.bind(5, std::max<std::int64_t>(0, filter.limit)).bind(6, std::max<std::int64_t>(0, filter.offset));
  Statement row(impl_->db, (std::string(kTrialSelect) + "WHERE t.id = ?").c_str());
  while (ids.step()) {
    row.reset();
    row.bind(1, ids.int64(0));
    if (row.step()) page.trials.push_back(read_trial(row));
  }
  return page;
}


std::vector<StrategySummary> Queries::strategies(std::int64_t campaign_id) const {
  return summary(campaign_id, 0.0).strategy_table;
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
  // Ordered as the index (trial_id, name, step) is, so SQLite does not sort; attempts are split here.
  Statement s(impl_->db,
              "SELECT name, attempt, step, value FROM metrics WHERE trial_id = ?1 AND (?2 IS NULL OR name = ?2) "
              "ORDER BY name, step");
  s.bind(1, trial_id).bind(2, name);
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
