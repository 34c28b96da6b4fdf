#include "podium/store/store.h"

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <tuple>

#include "podium/base/error.h"
#include "podium/base/suggest.h"
#include "podium/base/version.h"
#include "records.h"
#include "schema.h"
#include "sqlite.h"

namespace podium::store {

using base::RuntimeError;

double now_unix_s() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

struct Store::Impl {
  sqlite3* db = nullptr;
  std::filesystem::path path;
  int version = 0;
  // Hot-path statements are prepared once; the rest are prepared where used.
  std::map<const char*, std::unique_ptr<Statement>> cache;

  Statement& cached(const char* sql) {
    auto& slot = cache[sql];
    if (!slot) slot = std::make_unique<Statement>(db, sql);
    slot->reset();
    return *slot;
  }
  void exec(const char* sql) const {
    char* message = nullptr;
    if (sqlite3_exec(db, sql, nullptr, nullptr, &message) != SQLITE_OK) {
      const std::string text = message ? message : "unknown error";
      sqlite3_free(message);
      throw RuntimeError("database " + path.string() + ": " + text);
    }
  }
  ~Impl() {
    cache.clear();
    if (db) sqlite3_close_v2(db);
  }
};

namespace {

bool table_exists(sqlite3* db, const char* name) {
  Statement s(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
  s.bind(1, std::string(name));
  return s.step();
}

int read_version(sqlite3* db) {
  Statement s(db, "SELECT version FROM schema_version");
  return s.step() ? static_cast<int>(s.int64(0)) : 0;
}

std::string dump(const Json& j) { return j.dump(); }

CampaignRecord read_campaign(const Statement& s) {
  CampaignRecord c;
  c.id = s.int64(0);
  c.name = s.text(1);
  c.spec = parse_json(s.text(2));
  c.seed = static_cast<std::uint64_t>(s.int64(3));
  c.state = s.text(4);
  c.run_dir = s.text(5);
  c.podium_version = s.text(6);
  c.error = s.text(7);
  c.created_at = s.real(8);
  c.started_at = s.real(9);
  c.finished_at = s.real(10);
  return c;
}
constexpr const char* kCampaignColumns =
    "SELECT id, name, spec, seed, state, run_dir, podium_version, error, created_at, started_at, finished_at "
    "FROM campaigns ";

TrialCounts read_counts(Statement& s) {
  TrialCounts c;
  while (s.step()) add_to_counts(c, s.text(0), s.int64(1));  // one row per state
  return c;
}

}  // namespace

std::string shown_stage_state(const std::string& campaign_state, const std::string& stage_state) {
  const bool halted = campaign_state == "paused" || campaign_state == "cancelled";
  if (halted && stage_state == "running") return campaign_state;
  if (campaign_state == "cancelled" && stage_state == "waiting") return "cancelled";
  return stage_state;
}

std::int64_t find_campaign_id(const Store& store, const std::string& id_or_name) {
  if (const auto c = store.find_campaign(id_or_name)) return c->id;
  std::vector<std::string> names;
  for (const auto& c : store.campaigns())
    if (std::find(names.begin(), names.end(), c.name) == names.end()) names.push_back(c.name);
  const std::string near = base::did_you_mean(id_or_name, names);
  throw base::UserError("no campaign \"" + id_or_name + "\" in " + store.path().string() +
                        (near.empty() ? " (podium status lists them)" : near));
}

std::string trial_name(const std::string& stage, std::int64_t index) { return stage + "/" + std::to_string(index); }

Store::Store(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Store::~Store() = default;

int Store::latest_schema_version() { return static_cast<int>(kMigrations.size()); }
int Store::schema_version() const { return impl_->version; }
const std::filesystem::path& Store::path() const { return impl_->path; }

std::unique_ptr<Store> Store::open(const std::filesystem::path& path, Access access) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  const bool read_only = access == Access::read_only;
  if (read_only && !std::filesystem::exists(path)) throw RuntimeError(path.string() + ": no such database");
  if (read_only) {
    impl->db = open_for_reading(path);
  } else {
    // SQLite names the -wal file after the path it was given: two hard links, two -wal files, and
    // writes through both corrupt the database (sqlite.org/howtocorrupt.html, "multiple links").
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && st.st_nlink > 1)
      throw RuntimeError(path.string() + ": the database file has " + std::to_string(st.st_nlink) +
                         " hard links; SQLite cannot write it safely through more than one name: remove the "
                         "extra links (a symlink is fine)");
    const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX;
    const int rc = sqlite3_open_v2(path.c_str(), &impl->db, flags, nullptr);
    if (rc != SQLITE_OK)
      throw RuntimeError(path.string() + ": cannot open database: " + (impl->db ? sqlite3_errmsg(impl->db) : sqlite3_errstr(rc)));
  }
  sqlite3_busy_timeout(impl->db, 10000);
  impl->exec("PRAGMA foreign_keys = ON");

  // Check the version before anything writes: a newer database must stay untouched.
  try {
    const bool has_version = table_exists(impl->db, "schema_version");
    if (!has_version) {  // an empty file is new; any other content is someone else's database
      Statement any(impl->db, "SELECT count(*) FROM sqlite_master");
      any.step();
      if (any.int64(0) > 0) throw RuntimeError(path.string() + ": not a Podium database (no schema_version table)");
    }
    impl->version = has_version ? read_version(impl->db) : 0;
  } catch (const RuntimeError& e) {
    const std::string what = e.what();
    if (what.find("not a Podium") != std::string::npos) throw;
    throw RuntimeError(path.string() + ": cannot read database: " + what);
  }
  if (impl->version > latest_schema_version())
    throw RuntimeError(path.string() + ": database schema version " + std::to_string(impl->version) +
                       " is newer than this podium supports (" + std::to_string(latest_schema_version()) +
                       "); use a newer podium");
  if (read_only) {
    if (impl->version < latest_schema_version())
      throw RuntimeError(path.string() + ": database schema version " + std::to_string(impl->version) + " is older than " +
                         std::to_string(latest_schema_version()) +
                         "; run any writing podium command (e.g. podium run) to migrate it");
    return std::unique_ptr<Store>(new Store(std::move(impl)));
  }

  impl->exec("PRAGMA journal_mode = WAL");
  // NORMAL is durable across application crashes in WAL mode (only a power loss may drop the
  // last transactions), and keeps the scheduler's commit rate high.
  impl->exec("PRAGMA synchronous = NORMAL");
  for (int v = impl->version; v < latest_schema_version(); ++v) {
    impl->exec("BEGIN IMMEDIATE");
    try {
      impl->exec(kMigrations[v]);
      Statement s(impl->db, "UPDATE schema_version SET version = ?");
      s.bind(1, static_cast<std::int64_t>(v) + 1).run();
      impl->exec("COMMIT");
    } catch (...) {
      impl->exec("ROLLBACK");
      throw;
    }
    impl->version = v + 1;
  }
  return std::unique_ptr<Store>(new Store(std::move(impl)));
}

void Store::begin() { impl_->exec("BEGIN IMMEDIATE"); }
void Store::commit() { impl_->exec("COMMIT"); }
void Store::rollback() { sqlite3_exec(impl_->db, "ROLLBACK", nullptr, nullptr, nullptr); }

std::int64_t Store::add_campaign(const std::string& name, const Json& spec, std::uint64_t seed, const std::string& run_dir,
                                 const std::vector<NewStage>& stages) {
  std::int64_t id = 0;
  transaction([&] {
    Statement c(impl_->db,
                "INSERT INTO campaigns (name, spec, seed, state, run_dir, podium_version, created_at) "
                "VALUES (?, ?, ?, 'queued', ?, ?, ?)");
    c.bind(1, name).bind(2, dump(spec)).bind(3, static_cast<std::int64_t>(seed)).bind(4, run_dir);
    c.bind(5, std::string(base::version())).bind(6, now_unix_s()).run();
    id = sqlite3_last_insert_rowid(impl_->db);
    Statement s(impl_->db,
                "INSERT INTO stages (campaign_id, idx, name, task, algorithm, search_config, task_config, description, "
                "inputs, budget_trials, budget_seconds, state) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 'waiting')");
    for (std::size_t i = 0; i < stages.size(); ++i) {
      const auto& st = stages[i];
      s.bind(1, id).bind(2, static_cast<std::int64_t>(i)).bind(3, st.name).bind(4, st.task).bind(5, st.algorithm);
      s.bind(6, dump(st.search_config)).bind(7, dump(st.task_config)).bind(8, dump(st.description));
      s.bind(9, dump(st.inputs)).bind(10, st.budget_trials).bind(11, st.budget_seconds).run();
    }
  });
  return id;
}

std::vector<CampaignRecord> Store::campaigns() const {
  Statement s(impl_->db, (std::string(kCampaignColumns) + "ORDER BY id").c_str());
  std::vector<CampaignRecord> out;
  while (s.step()) out.push_back(read_campaign(s));
  return out;
}

std::optional<CampaignRecord> Store::campaign(std::int64_t id) const {
  Statement s(impl_->db, (std::string(kCampaignColumns) + "WHERE id = ?").c_str());
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_campaign(s);
}

std::optional<CampaignRecord> Store::find_campaign(const std::string& id_or_name) const {
  if (!id_or_name.empty() && id_or_name.find_first_not_of("0123456789") == std::string::npos) {
    if (auto c = campaign(std::stoll(id_or_name))) return c;
  }
  Statement s(impl_->db, (std::string(kCampaignColumns) + "WHERE name = ? ORDER BY id DESC LIMIT 1").c_str());
  s.bind(1, id_or_name);
  if (!s.step()) return std::nullopt;
  return read_campaign(s);
}

void Store::set_campaign_state(std::int64_t id, const std::string& state, const std::string& error) {
  const bool final_state = state == "done" || state == "failed" || state == "cancelled";
  Statement s(impl_->db,
              "UPDATE campaigns SET state = ?, error = ?, "
              "started_at = CASE WHEN ? = 'running' AND started_at = 0 THEN ? ELSE started_at END, "
              "finished_at = CASE WHEN ? THEN ? ELSE 0 END WHERE id = ?");
  const double now = now_unix_s();
  s.bind(1, state).bind(2, error).bind(3, state).bind(4, now).bind(5, static_cast<std::int64_t>(final_state));
  s.bind(6, now).bind(7, id).run();
}

std::vector<StageRecord> Store::stages(std::int64_t campaign_id) const {
  Statement s(impl_->db,
              "SELECT id, campaign_id, idx, name, task, algorithm, state, search_config, task_config, description, "
              "inputs, budget_trials, budget_seconds, elapsed_s, search_state, input_trials, error, told FROM stages "
              "WHERE campaign_id = ? ORDER BY idx");
  s.bind(1, campaign_id);
  std::vector<StageRecord> out;
  while (s.step()) {
    StageRecord r;
    r.id = s.int64(0);
    r.campaign_id = s.int64(1);
    r.index = static_cast<int>(s.int64(2));
    r.name = s.text(3);
    r.task = s.text(4);
    r.algorithm = s.text(5);
    r.state = s.text(6);
    r.search_config = parse_json(s.text(7));
    r.task_config = parse_json(s.text(8));
    r.description = parse_json(s.text(9));
    r.inputs = parse_json(s.text(10));
    r.budget_trials = s.int64(11);
    r.budget_seconds = s.real(12);
    r.elapsed_s = s.real(13);
    if (!s.is_null(14)) r.search_state = parse_json(s.text(14));
    if (!s.is_null(15)) r.input_trials = parse_json(s.text(15));
    r.error = s.text(16);
    r.told = s.int64(17);
    out.push_back(std::move(r));
  }
  return out;
}

void Store::start_stage(std::int64_t stage_id, const Json& input_trials, std::int64_t budget_trials) {
  Statement s(impl_->db, "UPDATE stages SET state = 'running', input_trials = ?, budget_trials = ? WHERE id = ?");
  input_trials.is_null() ? s.bind_null(1) : s.bind(1, dump(input_trials));
  s.bind(2, budget_trials).bind(3, stage_id).run();
}

void Store::set_stage_state(std::int64_t stage_id, const std::string& state, const std::string& error) {
  Statement s(impl_->db, "UPDATE stages SET state = ?, error = ? WHERE id = ?");
  s.bind(1, state).bind(2, error).bind(3, stage_id).run();
}

void Store::set_stage_budget(std::int64_t stage_id, std::int64_t budget_trials) {
  Statement s(impl_->db, "UPDATE stages SET budget_trials = ? WHERE id = ?");
  s.bind(1, budget_trials).bind(2, stage_id).run();
}

void Store::save_search_state(std::int64_t stage_id, const Json& state, double elapsed_s, std::int64_t told) {
  impl_->cached("UPDATE stages SET search_state = ?, elapsed_s = ?, told = ? WHERE id = ?")
      .bind(1, dump(state))
      .bind(2, elapsed_s)
      .bind(3, told)
      .bind(4, stage_id)
      .run();
}

std::int64_t Store::add_trial(std::int64_t stage_id, std::int64_t index, const Json& params, const Json& context,
                              const Json& info, std::uint64_t seed) {
  impl_
      ->cached(
          "INSERT INTO trials (stage_id, idx, params, context, info, seed, state, created_at) "
          "VALUES (?, ?, ?, ?, ?, ?, 'pending', ?)")
      .bind(1, stage_id)
      .bind(2, index)
      .bind(3, dump(params))
      .bind(4, dump(context))
      .bind(5, dump(info))
      .bind(6, static_cast<std::int64_t>(seed))
      .bind(7, now_unix_s())
      .run();
  return sqlite3_last_insert_rowid(impl_->db);
}

namespace {
std::vector<TrialRecord> read_trials(sqlite3* db, Statement& s) {
  Statement features(db, kTrialFeatures);
  std::vector<TrialRecord> out;
  while (s.step()) {
    out.push_back(read_trial(s));
    out.back().features = read_features(features, out.back().id);
  }
  return out;
}
}  // namespace

std::vector<TrialRecord> Store::trials(std::int64_t stage_id) const {
  Statement s(impl_->db, (std::string(kTrialSelect) + "WHERE t.stage_id = ? ORDER BY t.idx").c_str());
  s.bind(1, stage_id);
  return read_trials(impl_->db, s);
}

std::vector<TrialRecord> Store::campaign_trials(std::int64_t campaign_id) const {
  Statement s(impl_->db,
              (std::string(kTrialSelect) + "JOIN stages st ON st.id = t.stage_id WHERE st.campaign_id = ? ORDER BY st.idx, t.idx")
                  .c_str());
  s.bind(1, campaign_id);
  return read_trials(impl_->db, s);
}

std::optional<TrialRecord> Store::trial(std::int64_t trial_id) const {
  Statement s(impl_->db, (std::string(kTrialSelect) + "WHERE t.id = ?").c_str());
  s.bind(1, trial_id);
  auto trials = read_trials(impl_->db, s);
  if (trials.empty()) return std::nullopt;
  return std::move(trials.front());
}

std::vector<TrialOutcome> Store::done_trials(std::int64_t stage_id) const {
  // trials_by_state (stage_id, state, idx) gives the order; result_info is read only where it
  // names a table (plugins/task.h "Result tables"), so a 100,000-trial stage parses no JSON.
  Statement s(impl_->db,
              "SELECT id, idx, objective, strategy, finished_at, "
              "CASE WHEN instr(result_info, '\"table\"') > 0 THEN result_info ELSE '' END "
              "FROM trials WHERE stage_id = ? AND state = 'done' ORDER BY idx");
  s.bind(1, stage_id);
  std::vector<TrialOutcome> out;
  while (s.step()) {
    TrialOutcome t;
    t.id = s.int64(0);
    t.index = s.int64(1);
    if (!s.is_null(2)) t.objective = s.real(2);
    if (!s.is_null(3)) t.strategy = s.int64(3);
    t.finished_at = s.real(4);
    t.result_info = s.text(5);
    out.push_back(std::move(t));
  }
  return out;
}

StrategyLabels Store::strategy_labels(std::int64_t stage_id) const {
  // The order strategies were first found is the order of their first done trials in finishing
  // order (finished_at, idx): one probe of trials_by_strategy_finish per strategy the stage's
  // counts hold, however late a strategy was found (a walk of the done trials until every
  // strategy showed read up to all of them).
  Statement list(impl_->db, "SELECT strategy FROM stage_strategy_counts WHERE stage_id = ? AND trials > 0");
  list.bind(1, stage_id);
  Statement first(impl_->db,
                  "SELECT finished_at, idx FROM trials WHERE stage_id = ?1 AND strategy = ?2 AND state = 'done' "
                  "ORDER BY finished_at, idx LIMIT 1");
  std::vector<std::tuple<double, std::int64_t, std::int64_t>> found;  // (finished_at, idx, strategy)
  while (list.step()) {
    first.reset();
    first.bind(1, stage_id).bind(2, list.int64(0));
    if (first.step()) found.emplace_back(first.real(0), first.int64(1), list.int64(0));
  }
  std::sort(found.begin(), found.end());
  StrategyLabels labels;
  for (const auto& f : found) labels.emplace(std::get<2>(f), static_cast<std::int64_t>(labels.size()) + 1);
  return labels;
}

std::string Store::summary_token(std::int64_t campaign_id) const {
  std::string token;
  const auto add = [&token](Statement& s, int columns) {
    while (s.step())
      for (int i = 0; i < columns; ++i) token += (s.is_null(i) ? std::string("-") : s.text(i)) + (i + 1 < columns ? "," : ";");
  };
  Statement campaign(impl_->db, "SELECT state FROM campaigns WHERE id = ?");
  campaign.bind(1, campaign_id);
  add(campaign, 1);
  Statement stages(impl_->db,
                   "SELECT st.id, st.state, st.budget_trials, "
                   "(SELECT max(finished_at) FROM trials t WHERE t.stage_id = st.id AND t.state = 'done') "
                   "FROM stages st WHERE st.campaign_id = ? ORDER BY st.idx");
  stages.bind(1, campaign_id);
  add(stages, 4);
  Statement states(impl_->db,
                   "SELECT c.stage_id, c.state, c.trials FROM stages st JOIN stage_state_counts c ON c.stage_id = st.id "
                   "WHERE st.campaign_id = ? ORDER BY c.stage_id, c.state");
  states.bind(1, campaign_id);
  add(states, 3);
  Statement strategies(
      impl_->db,
      "SELECT c.stage_id, c.strategy, c.trials FROM stages st JOIN stage_strategy_counts c ON c.stage_id = st.id "
      "WHERE st.campaign_id = ? ORDER BY c.stage_id, c.strategy");
  strategies.bind(1, campaign_id);
  add(strategies, 3);
  return token;
}

// From the counts the triggers keep (schema v3): a few rows, not a scan of the trials.
TrialCounts Store::trial_counts(std::int64_t campaign_id) const {
  Statement s(impl_->db,
              "SELECT c.state, sum(c.trials) FROM stages st JOIN stage_state_counts c ON c.stage_id = st.id "
              "WHERE st.campaign_id = ? GROUP BY c.state");
  s.bind(1, campaign_id);
  return read_counts(s);
}

TrialCounts Store::stage_trial_counts(std::int64_t stage_id) const {
  Statement s(impl_->db, "SELECT state, trials FROM stage_state_counts WHERE stage_id = ?");
  s.bind(1, stage_id);
  return read_counts(s);
}

std::int64_t Store::start_attempt(std::int64_t trial_id, int number, const std::string& worker, const std::string& host,
                                  const std::string& job_id) {
  const double now = now_unix_s();
  impl_
      ->cached(
          "INSERT INTO attempts (trial_id, number, state, worker, host, job_id, started_at) "
          "VALUES (?, ?, 'running', ?, ?, ?, ?)")
      .bind(1, trial_id)
      .bind(2, static_cast<std::int64_t>(number))
      .bind(3, worker)
      .bind(4, host)
      .bind(5, job_id)
      .bind(6, now)
      .run();
  const std::int64_t id = sqlite3_last_insert_rowid(impl_->db);
  impl_->cached("UPDATE trials SET state = 'running', attempts = ?, started_at = ? WHERE id = ?")
      .bind(1, static_cast<std::int64_t>(number))
      .bind(2, now)
      .bind(3, trial_id)
      .run();
  return id;
}

void Store::finish_attempt(std::int64_t attempt_id, const std::string& state, const std::string& error,
                           std::optional<int> exit_code, std::optional<int> signal) {
  auto& s = impl_->cached(
      "UPDATE attempts SET state = ?, error = ?, exit_code = ?, signal = ?, finished_at = ? "
      "WHERE id = ?");
  s.bind(1, state).bind(2, error);
  exit_code ? s.bind(3, static_cast<std::int64_t>(*exit_code)) : s.bind_null(3);
  signal ? s.bind(4, static_cast<std::int64_t>(*signal)) : s.bind_null(4);
  s.bind(5, now_unix_s()).bind(6, attempt_id).run();
}

void Store::complete_trial(std::int64_t trial_id, const std::vector<double>& objectives,
                           const std::vector<std::string>& feature_names, const std::vector<double>& features,
                           const Json& result_info, const std::vector<ArtifactRecord>& artifacts) {
  auto& t = impl_->cached(
      "UPDATE trials SET state = 'done', objectives = ?, objective = ?, result_info = ?, error = '', finished_at = ? "
      "WHERE id = ?");
  t.bind(1, dump(Json(objectives)));
  objectives.empty() ? t.bind_null(2) : t.bind(2, objectives[0]);
  t.bind(3, dump(result_info)).bind(4, now_unix_s()).bind(5, trial_id).run();
  auto& f = impl_->cached("INSERT INTO features (trial_id, idx, name, value) VALUES (?, ?, ?, ?)");
  for (std::size_t i = 0; i < features.size(); ++i) {
    f.bind(1, trial_id).bind(2, static_cast<std::int64_t>(i));
    f.bind(3, i < feature_names.size() ? feature_names[i] : "f" + std::to_string(i)).bind(4, features[i]).run();
  }
  auto& a = impl_->cached("INSERT INTO artifacts (trial_id, name, path, sha256, size_bytes) VALUES (?, ?, ?, ?, ?)");
  for (const auto& art : artifacts)
    a.bind(1, trial_id).bind(2, art.name).bind(3, art.path).bind(4, art.sha256).bind(5, art.size_bytes).run();
}

void Store::set_trial_state(std::int64_t trial_id, const std::string& state, const std::string& error) {
  const bool final_state = state == "failed" || state == "cancelled";
  impl_
      ->cached(
          "UPDATE trials SET state = ?, error = ?, finished_at = CASE WHEN ? THEN ? ELSE finished_at END "
          "WHERE id = ?")
      .bind(1, state)
      .bind(2, error)
      .bind(3, static_cast<std::int64_t>(final_state))
      .bind(4, now_unix_s())
      .bind(5, trial_id)
      .run();
}

void Store::set_trial_strategy(std::int64_t trial_id, std::int64_t strategy) {
  impl_->cached("UPDATE trials SET strategy = ? WHERE id = ?").bind(1, strategy).bind(2, trial_id).run();
}

void Store::set_attempt_placement(std::int64_t attempt_id, const std::string& job_id, const std::string& host) {
  impl_
      ->cached(
          "UPDATE attempts SET job_id = ?, host = CASE WHEN ? = '' THEN host ELSE ? END, "
          "worker = CASE WHEN ? = '' THEN worker ELSE 'slurm job ' || ? END WHERE id = ?")
      .bind(1, job_id)
      .bind(2, host)
      .bind(3, host)
      .bind(4, job_id)
      .bind(5, job_id)
      .bind(6, attempt_id)
      .run();
}

namespace {
constexpr const char* kAttemptColumns =
    "SELECT a.id, a.trial_id, a.number, a.state, a.worker, a.host, a.job_id, a.exit_code, a.signal, a.error, "
    "a.started_at, a.finished_at FROM attempts a ";

std::vector<AttemptRecord> read_attempts(Statement& s) {
  std::vector<AttemptRecord> out;
  while (s.step()) {
    AttemptRecord a;
    a.id = s.int64(0);
    a.trial_id = s.int64(1);
    a.number = static_cast<int>(s.int64(2));
    a.state = s.text(3);
    a.worker = s.text(4);
    a.host = s.text(5);
    a.job_id = s.text(6);
    if (!s.is_null(7)) a.exit_code = static_cast<int>(s.int64(7));
    if (!s.is_null(8)) a.signal = static_cast<int>(s.int64(8));
    a.error = s.text(9);
    a.started_at = s.real(10);
    a.finished_at = s.real(11);
    out.push_back(std::move(a));
  }
  return out;
}
}  // namespace

std::vector<AttemptRecord> Store::attempts(std::int64_t trial_id) const {
  Statement s(impl_->db, (std::string(kAttemptColumns) + "WHERE a.trial_id = ? ORDER BY a.number").c_str());
  s.bind(1, trial_id);
  return read_attempts(s);
}

std::vector<AttemptRecord> Store::running_attempts(std::int64_t stage_id) const {
  Statement s(impl_->db,
              (std::string(kAttemptColumns) + "JOIN trials t ON t.id = a.trial_id WHERE t.stage_id = ? AND a.state = 'running' "
                                              "ORDER BY t.idx")
                  .c_str());
  s.bind(1, stage_id);
  return read_attempts(s);
}

std::vector<ArtifactRecord> Store::artifacts(std::int64_t trial_id) const {
  Statement s(impl_->db, "SELECT name, path, sha256, size_bytes FROM artifacts WHERE trial_id = ? ORDER BY id");
  s.bind(1, trial_id);
  std::vector<ArtifactRecord> out;
  while (s.step()) out.push_back({s.text(0), s.text(1), s.text(2), s.int64(3)});
  return out;
}

void Store::add_metrics(std::int64_t trial_id, const std::vector<MetricPoint>& points) {
  // metrics_by_trial (trial_id, name, step) answers the probe.
  auto& s = impl_->cached(
      "INSERT INTO metrics (trial_id, attempt, name, step, value) SELECT ?1, ?2, ?3, ?4, ?5 WHERE NOT EXISTS "
      "(SELECT 1 FROM metrics WHERE trial_id = ?1 AND name = ?3 AND step = ?4)");
  for (const auto& p : points) {
    s.bind(1, trial_id).bind(2, static_cast<std::int64_t>(p.attempt)).bind(3, p.name).bind(4, p.step);
    std::isfinite(p.value) ? s.bind(5, p.value) : s.bind_null(5);  // NaN is stored as NULL
    s.run();
  }
}

std::vector<MetricPoint> Store::metrics(std::int64_t trial_id) const {
  Statement s(impl_->db, "SELECT name, step, value, attempt FROM metrics WHERE trial_id = ? ORDER BY name, attempt, step");
  s.bind(1, trial_id);
  std::vector<MetricPoint> out;
  while (s.step()) out.push_back({s.text(0), s.real(1), s.is_null(2) ? std::nan("") : s.real(2), static_cast<int>(s.int64(3))});
  return out;
}

void Store::add_event(std::int64_t campaign_id, const std::string& kind, const Json& payload) {
  impl_->cached("INSERT INTO events (campaign_id, time, kind, payload) VALUES (?, ?, ?, ?)")
      .bind(1, campaign_id)
      .bind(2, now_unix_s())
      .bind(3, kind)
      .bind(4, dump(payload))
      .run();
}

std::vector<Json> Store::events(std::int64_t campaign_id) const {
  Statement s(impl_->db, "SELECT time, kind, payload FROM events WHERE campaign_id = ? ORDER BY id");
  s.bind(1, campaign_id);
  std::vector<Json> out;
  while (s.step()) out.push_back({{"time", s.real(0)}, {"kind", s.text(1)}, {"payload", parse_json(s.text(2))}});
  return out;
}

int Store::recover_interrupted() {
  int changed = 0;
  transaction([&] {
    Statement a(impl_->db,
                "UPDATE attempts SET state = 'interrupted', error = 'scheduler stopped while the attempt ran', "
                "finished_at = ? WHERE state = 'running' AND job_id = ''");
    a.bind(1, now_unix_s()).run();
    changed = sqlite3_changes(impl_->db);
    impl_->exec(
        "UPDATE trials SET state = 'interrupted' WHERE state = 'running' AND NOT EXISTS "
        "(SELECT 1 FROM attempts a WHERE a.trial_id = trials.id AND a.state = 'running')");
  });
  return changed;
}

}  // namespace podium::store
