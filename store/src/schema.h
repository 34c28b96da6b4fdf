#pragma once
// The schema as forward migrations: kMigrations[i] brings a database from version i to i + 1.
// Never edit a released migration; add a new one (and a saved database of the old version to
// tests/store/testdata).
#include <array>

namespace podium::store {

inline constexpr std::array<const char*, 2> kMigrations = {
    // Version 1: campaigns, stages, trials, attempts, metrics, features, artifacts, events.
    R"sql(
CREATE TABLE schema_version (version INTEGER NOT NULL);
INSERT INTO schema_version (version) VALUES (0);
CREATE TABLE campaigns (
  id INTEGER PRIMARY KEY,
  name TEXT NOT NULL,
  spec TEXT NOT NULL,
  seed INTEGER NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('queued','running','paused','done','failed','cancelled')),
  run_dir TEXT NOT NULL,
  podium_version TEXT NOT NULL,
  error TEXT NOT NULL DEFAULT '',
  created_at REAL NOT NULL,
  started_at REAL NOT NULL DEFAULT 0,
  finished_at REAL NOT NULL DEFAULT 0
);
CREATE TABLE stages (
  id INTEGER PRIMARY KEY,
  campaign_id INTEGER NOT NULL REFERENCES campaigns(id) ON DELETE CASCADE,
  idx INTEGER NOT NULL,
  name TEXT NOT NULL,
  task TEXT NOT NULL,
  algorithm TEXT NOT NULL,
  search_config TEXT NOT NULL,
  task_config TEXT NOT NULL,
  description TEXT NOT NULL,
  inputs TEXT NOT NULL,
  budget_trials INTEGER NOT NULL,
  budget_seconds REAL NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('waiting','running','done','failed')),
  search_state TEXT,
  elapsed_s REAL NOT NULL DEFAULT 0,
  UNIQUE (campaign_id, idx)
);
CREATE TABLE trials (
  id INTEGER PRIMARY KEY,
  stage_id INTEGER NOT NULL REFERENCES stages(id) ON DELETE CASCADE,
  idx INTEGER NOT NULL,
  params TEXT NOT NULL,
  context TEXT NOT NULL,
  info TEXT NOT NULL,
  seed INTEGER NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('pending','running','done','failed','interrupted','cancelled')),
  attempts INTEGER NOT NULL DEFAULT 0,
  objectives TEXT,
  result_info TEXT,
  strategy INTEGER,
  error TEXT NOT NULL DEFAULT '',
  created_at REAL NOT NULL,
  started_at REAL NOT NULL DEFAULT 0,
  finished_at REAL NOT NULL DEFAULT 0,
  UNIQUE (stage_id, idx)
);
CREATE INDEX trials_by_state ON trials (stage_id, state);
CREATE TABLE attempts (
  id INTEGER PRIMARY KEY,
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  number INTEGER NOT NULL,
  state TEXT NOT NULL CHECK (state IN ('running','done','failed','timeout','interrupted','cancelled')),
  worker TEXT NOT NULL,
  host TEXT NOT NULL,
  job_id TEXT NOT NULL DEFAULT '',
  exit_code INTEGER,
  signal INTEGER,
  error TEXT NOT NULL DEFAULT '',
  started_at REAL NOT NULL,
  finished_at REAL NOT NULL DEFAULT 0,
  UNIQUE (trial_id, number)
);
CREATE TABLE metrics (
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  attempt INTEGER NOT NULL,
  name TEXT NOT NULL,
  step REAL NOT NULL,
  value REAL
);
CREATE INDEX metrics_by_trial ON metrics (trial_id, name, step);
CREATE TABLE features (
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  idx INTEGER NOT NULL,
  name TEXT NOT NULL,
  value REAL NOT NULL,
  PRIMARY KEY (trial_id, idx)
);
CREATE TABLE artifacts (
  id INTEGER PRIMARY KEY,
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  path TEXT NOT NULL,
  sha256 TEXT NOT NULL,
  size_bytes INTEGER NOT NULL
);
CREATE TABLE events (
  id INTEGER PRIMARY KEY,
  campaign_id INTEGER NOT NULL REFERENCES campaigns(id) ON DELETE CASCADE,
  time REAL NOT NULL,
  kind TEXT NOT NULL,
  payload TEXT NOT NULL
);
)sql",
    // Version 2: the primary objective as a number, and covering indexes, so the dashboard sorts
    // and summarises 100,000-trial campaigns from indexes alone, without parsing JSON.
    R"sql(
ALTER TABLE trials ADD COLUMN objective REAL;
UPDATE trials SET objective = json_extract(objectives, '$[0]') WHERE objectives IS NOT NULL;
CREATE INDEX trials_by_objective ON trials (stage_id, objective);
CREATE INDEX trials_by_strategy ON trials (stage_id, strategy, objective);
CREATE INDEX trials_by_finish ON trials (stage_id, state, finished_at);
)sql",
};

}  // namespace podium::store
