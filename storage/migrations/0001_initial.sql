-- Scenarios with their source, runs (batches of episodes), episodes with their metrics, events and
-- sampled trajectories (DESIGN.md §4). Times are RFC 3339 UTC text.
CREATE TABLE scenarios (
  id          TEXT PRIMARY KEY,
  name        TEXT NOT NULL,
  format      TEXT NOT NULL CHECK (format IN ('json', 'imhus_xml', 'pedsim_xml')),
  source      TEXT NOT NULL,
  sha256      TEXT NOT NULL CHECK (length(sha256) = 64),
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
) STRICT;
CREATE INDEX scenarios_by_hash ON scenarios (sha256);

CREATE TABLE runs (
  id          TEXT PRIMARY KEY,
  scenario_id TEXT NOT NULL REFERENCES scenarios (id),
  controller  TEXT NOT NULL,
  config      TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(config)),
  status      TEXT NOT NULL CHECK (status IN ('queued', 'running', 'finished', 'failed', 'cancelled')),
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now')),
  finished_at TEXT
) STRICT;
CREATE INDEX runs_by_scenario ON runs (scenario_id);

CREATE TABLE episodes (
  id                 TEXT PRIMARY KEY,
  run_id             TEXT REFERENCES runs (id) ON DELETE CASCADE,
  scenario_id        TEXT NOT NULL REFERENCES scenarios (id),
  seed               INTEGER NOT NULL,
  controller         TEXT NOT NULL,
  status             TEXT NOT NULL,
  termination_reason TEXT NOT NULL,
  ticks              INTEGER NOT NULL CHECK (ticks >= 0),
  sim_time           REAL NOT NULL CHECK (sim_time >= 0),
  created_at         TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))
) STRICT;
CREATE INDEX episodes_by_run ON episodes (run_id);
CREATE INDEX episodes_by_scenario ON episodes (scenario_id);

-- A metric without a finite value keeps the reason instead (never NaN or infinity).
CREATE TABLE metric_values (
  episode_id  TEXT NOT NULL REFERENCES episodes (id) ON DELETE CASCADE,
  key         TEXT NOT NULL,
  value       REAL,
  null_reason TEXT,
  CHECK ((value IS NULL) = (null_reason IS NOT NULL)),
  PRIMARY KEY (episode_id, key)
) STRICT, WITHOUT ROWID;

CREATE TABLE events (
  episode_id TEXT NOT NULL REFERENCES episodes (id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  tick       INTEGER NOT NULL,
  time       REAL NOT NULL,
  kind       TEXT NOT NULL,
  subject    TEXT NOT NULL DEFAULT '',
  data       TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(data)),
  PRIMARY KEY (episode_id, seq)
) STRICT, WITHOUT ROWID;

CREATE TABLE trajectory_samples (
  episode_id TEXT NOT NULL REFERENCES episodes (id) ON DELETE CASCADE,
  agent_id   TEXT NOT NULL,
  tick       INTEGER NOT NULL,
  x          REAL NOT NULL,
  y          REAL NOT NULL,
  theta      REAL NOT NULL,
  PRIMARY KEY (episode_id, agent_id, tick)
) STRICT, WITHOUT ROWID;
