#pragma once
// The schema as forward migrations: kMigrations[i] brings a database from version i to i + 1.
// Never edit a released migration; add a new one (and a saved database of the old version to
// tests/store/testdata).
#include <array>

namespace podium::store {

inline constexpr std::array<const char*, 6> kMigrations = {
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
    // Version 3, what the dashboard reads from a 100,000-trial campaign without scanning it:
    // - trial counts per (stage, state) and per (stage, strategy), kept by triggers in the same
    //   transaction as every change to trials (summaries and page totals read a few rows; the rest
    //   of a summary is min/max probes of the v2 indexes). A row that falls to 0 stays (readers
    //   skip it), so each trigger is one update or upsert.
    // - trials_by_state gains idx: the scatter's walk over done trials and state-filtered pages in
    //   index order read that index only.
    // - features keyed by (trial, idx) WITHOUT ROWID: a trial's features are one b-tree seek.
    R"sql(
CREATE TABLE stage_state_counts (
  stage_id INTEGER NOT NULL REFERENCES stages(id) ON DELETE CASCADE,
  state TEXT NOT NULL,
  trials INTEGER NOT NULL,
  PRIMARY KEY (stage_id, state)
) WITHOUT ROWID;
CREATE TABLE stage_strategy_counts (
  stage_id INTEGER NOT NULL REFERENCES stages(id) ON DELETE CASCADE,
  strategy INTEGER NOT NULL,
  trials INTEGER NOT NULL,
  PRIMARY KEY (stage_id, strategy)
) WITHOUT ROWID;
INSERT INTO stage_state_counts SELECT stage_id, state, count(*) FROM trials GROUP BY stage_id, state;
INSERT INTO stage_strategy_counts
  SELECT stage_id, strategy, count(*) FROM trials WHERE strategy IS NOT NULL GROUP BY stage_id, strategy;
CREATE TRIGGER trials_counted_on_insert AFTER INSERT ON trials BEGIN
  INSERT INTO stage_state_counts VALUES (new.stage_id, new.state, 1)
    ON CONFLICT DO UPDATE SET trials = trials + 1;
  INSERT INTO stage_strategy_counts SELECT new.stage_id, new.strategy, 1 WHERE new.strategy IS NOT NULL
    ON CONFLICT DO UPDATE SET trials = trials + 1;
END;
CREATE TRIGGER trials_counted_on_delete AFTER DELETE ON trials BEGIN
  UPDATE stage_state_counts SET trials = trials - 1 WHERE stage_id = old.stage_id AND state = old.state;
  UPDATE stage_strategy_counts SET trials = trials - 1 WHERE stage_id = old.stage_id AND strategy = old.strategy;
END;
CREATE TRIGGER trials_counted_on_state AFTER UPDATE OF stage_id, state ON trials
  WHEN old.state IS NOT new.state OR old.stage_id IS NOT new.stage_id BEGIN
  UPDATE stage_state_counts SET trials = trials - 1 WHERE stage_id = old.stage_id AND state = old.state;
  INSERT INTO stage_state_counts VALUES (new.stage_id, new.state, 1)
    ON CONFLICT DO UPDATE SET trials = trials + 1;
END;
CREATE TRIGGER trials_counted_on_strategy AFTER UPDATE OF stage_id, strategy ON trials
  WHEN old.strategy IS NOT new.strategy OR old.stage_id IS NOT new.stage_id BEGIN
  UPDATE stage_strategy_counts SET trials = trials - 1 WHERE stage_id = old.stage_id AND strategy = old.strategy;
  INSERT INTO stage_strategy_counts SELECT new.stage_id, new.strategy, 1 WHERE new.strategy IS NOT NULL
    ON CONFLICT DO UPDATE SET trials = trials + 1;
END;
DROP INDEX trials_by_state;
CREATE INDEX trials_by_state ON trials (stage_id, state, idx);
CREATE TABLE features_by_trial (
  trial_id INTEGER NOT NULL REFERENCES trials(id) ON DELETE CASCADE,
  idx INTEGER NOT NULL,
  name TEXT NOT NULL,
  value REAL NOT NULL,
  PRIMARY KEY (trial_id, idx)
) WITHOUT ROWID;
INSERT INTO features_by_trial SELECT trial_id, idx, name, value FROM features;
DROP TABLE features;
ALTER TABLE features_by_trial RENAME TO features;
)sql",
    // Version 4, stage hand-over and stage failures: the earlier trials a stage's inputs selected,
    // resolved when it started (JSON array; NULL before, or without inputs), so a resumed stage
    // hands over exactly what it did before; and why a stage failed.
    R"sql(
ALTER TABLE stages ADD COLUMN input_trials TEXT;
ALTER TABLE stages ADD COLUMN error TEXT NOT NULL DEFAULT '';
)sql",
    // Version 5, results told in trial order: how many of a stage's trials (in the order they were
    // asked) the search has been told; later finished ones wait for the earlier ones. Earlier
    // schedulers told every finished trial at once, which this count approximates.
    R"sql(
ALTER TABLE stages ADD COLUMN told INTEGER NOT NULL DEFAULT 0;
UPDATE stages SET told = (SELECT count(*) FROM trials
                          WHERE trials.stage_id = stages.id AND trials.state IN ('done', 'failed', 'cancelled'));
)sql",
    // Version 6, the dashboard's campaign page and metric plots without table lookups or scans
    // (indexes only: no data changes; written to run again harmlessly on a database that has them):
    // - metrics_by_series covers a metric series (attempt and value too), so a 100,000-point plot
    //   is one index range, not 100,000 row lookups; it replaces metrics_by_trial (its prefix).
    // - trials_by_strategy_finish: each strategy's first done trial in finishing order is one
    //   probe (strategy labels), not a walk of the stage's done trials until every strategy shows.
    // - artifacts and events by their trial and campaign: they were scanned whole per lookup.
    R"sql(
CREATE INDEX IF NOT EXISTS metrics_by_series ON metrics (trial_id, name, step, attempt, value);
DROP INDEX IF EXISTS metrics_by_trial;
CREATE INDEX IF NOT EXISTS trials_by_strategy_finish ON trials (stage_id, strategy, state, finished_at, idx);
CREATE INDEX IF NOT EXISTS artifacts_by_trial ON artifacts (trial_id);
CREATE INDEX IF NOT EXISTS events_by_campaign ON events (campaign_id);
)sql",
};

}  // namespace podium::store
